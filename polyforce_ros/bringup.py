"""``polyforce bringup``: launch/polyforce.launch.py for installs without ROS launch (PyPI).

Starts the node executables as child processes, each with its parameter file
from ``config/`` (the shipped one, or the package share's) and the command
line's overrides, waits, and on Ctrl-C / SIGTERM stops them in the reverse of
the start order, each by its PID: SIGINT, then SIGKILL after ``stop_timeout_s``.

Start order: recorder (``--record``), haptic bridge (``--with-bridge``),
compensation, driver. So on shutdown the driver stops first, the compensation
node publishes its last zero wrench, the bridge ramps its command to zero and
publishes a last zero command, and the recorder still records all of it.
If a child exits on its own, the others are stopped and bringup exits 1.

Children run in their own process group (a terminal's Ctrl-C reaches only
bringup, which orders the shutdown) and, on Linux, get SIGTERM if bringup dies
(their SIGTERM handler publishes the last zero like SIGINT does).
"""
from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path
from types import FrameType
from typing import Any, Callable, Iterable, Optional, Union

import yaml

from . import contract

PACKAGE = "polyforce_ros"
#: Parameter file of each node executable in config/ (the recorder has none).
PARAM_FILES = {
    "driver_node": "driver.yaml",
    "compensation_node": "compensation.yaml",
    "haptic_bridge_node": "haptic_bridge.yaml",
}
STOP_TIMEOUT_S = 10.0
#: A path as the command line or a caller gives it.
StrPath = Union[str, os.PathLike[str]]


def node_set(with_bridge: bool = False, record: bool = False) -> list[str]:
    """The node executables of a bring-up, in start order (shutdown runs in reverse): the recorder first, so it
    records every last zero; the haptic bridge; the compensation node; the driver last. Read by ``plan`` and by
    launch/polyforce.launch.py."""
    return ((["recorder_node"] if record else []) + (["haptic_bridge_node"] if with_bridge else [])
            + ["compensation_node", "driver_node"])


def driver_waits_for(names: Iterable[str]) -> int:
    """How many readers of bridge_voltage among ``names`` the simulated profile waits for before it starts: a
    compensation node that joined late would see a moving sensor and could not zero; a late recorder would miss
    the first samples."""
    return sum(name in ("compensation_node", "recorder_node") for name in names)


@dataclass
class ChildSpec:
    """One node process: executable name, full argv and where its parameters came from."""

    name: str
    argv: list[str]
    params_file: Path
    source: str = ""
    overrides: dict[str, object] = field(default_factory=dict)


def config_dir() -> Path:
    """The shipped config/: the package share (colcon or ``pip install .``), else the source tree."""
    candidates = []
    try:
        from ament_index_python.packages import get_package_share_directory

        candidates.append(Path(get_package_share_directory(PACKAGE)) / "config")
    except Exception:  # noqa: BLE001 - no ament index entry in a plain or editable venv
        pass
    candidates += [Path(sys.prefix) / "share" / PACKAGE / "config", Path(__file__).resolve().parents[1] / "config"]
    for candidate in candidates:
        if all((candidate / f).is_file() for f in PARAM_FILES.values()):
            return candidate
    raise FileNotFoundError(f"no polyforce_ros config/ with {sorted(PARAM_FILES.values())} in {[str(c) for c in candidates]}")


def node_command(name: str) -> list[str]:
    """argv prefix that runs node executable ``name``.

    The executable next to the running ``polyforce`` (colcon: lib/polyforce_ros/, venv: bin/) or next
    to the interpreter, else ``python -m polyforce_ros.nodes.<name>`` with this interpreter.
    """
    for folder in (Path(sys.argv[0]).absolute().parent, Path(sys.executable).parent):
        exe = folder / name
        if exe.is_file() and os.access(exe, os.X_OK):
            return [str(exe)]
    return [sys.executable, "-m", f"{PACKAGE}.nodes.{name}"]


def load_params(path: StrPath) -> dict[str, Any]:
    """The ros__parameters of a parameter file's one node section."""
    data = yaml.safe_load(Path(path).read_text()) or {}
    sections = [v["ros__parameters"] for v in data.values() if isinstance(v, dict) and "ros__parameters" in v]
    if len(sections) != 1:
        raise ValueError(f"{path}: expected one node section with ros__parameters, found {len(sections)}")
    return dict(sections[0])


def plan(workdir: StrPath, backend: Optional[str] = None, port: Optional[str] = None, model: Optional[StrPath] = None,
         with_bridge: bool = False, record: Optional[StrPath] = None, namespace: str = contract.NAMESPACE,
         config: Optional[StrPath] = None) -> list[ChildSpec]:
    """The child processes in start order, with their parameter files written to ``workdir``.

    Each node gets one parameter file: its config/ file's parameters plus the overrides, under the
    node's fully qualified name in ``namespace`` (so they apply in any namespace, and values are
    YAML-quoted instead of parsed from ``-p`` arguments).
    """
    workdir, config = Path(workdir), Path(config) if config else config_dir()
    namespace = "/" + namespace.strip("/")
    if backend not in (None, "sim", "serial"):
        raise ValueError(f"backend must be sim or serial, got {backend!r}")
    overrides: dict[str, dict[str, object]] = {"driver_node": {}, "compensation_node": {}, "haptic_bridge_node": {},
                                               "recorder_node": {}}
    if backend:
        overrides["driver_node"]["backend"] = backend
    if port:
        overrides["driver_node"]["port"] = str(port)
    if model:
        model = Path(model).expanduser().resolve()
        if not model.is_file():
            raise FileNotFoundError(f"model file {model} not found")
        overrides["compensation_node"]["model_file"] = str(model)
    names = node_set(with_bridge, bool(record))
    if record:
        overrides["recorder_node"]["bag_path"] = str(Path(record).expanduser().resolve())
    overrides["driver_node"]["wait_for_subscribers"] = driver_waits_for(names)
    specs: list[ChildSpec] = []
    for name in names:
        source = config / PARAM_FILES[name] if name in PARAM_FILES else None
        params = dict(load_params(source) if source else {}, **overrides[name])
        params_file = workdir / f"{name}.yaml"
        params_file.write_text(yaml.safe_dump({f"{namespace}/{name}": {"ros__parameters": params}}, sort_keys=False))
        argv = node_command(name) + ["--ros-args", "-r", f"__ns:={namespace}", "--params-file", str(params_file)]
        specs.append(ChildSpec(name, argv, params_file, str(source or ""), overrides[name]))
    return specs


def describe(specs: Iterable[ChildSpec]) -> str:
    lines = []
    for spec in specs:
        extra = ", ".join(f"{k}={v}" for k, v in spec.overrides.items())
        lines.append(f"{spec.name}: {spec.source or '(no parameter file)'}" + (f" + {extra}" if extra else ""))
        lines.append("    " + " ".join(spec.argv))
    return "\n".join(lines)


def _child_setup() -> None:
    """Runs in each child between fork and exec. SIGINT is the polite stop (:meth:`Bringup.stop`): a bringup started
    where SIGINT is ignored (a background job of a script, nohup) would pass the ignoring on through exec, and every
    node would be killed after the timeout without its last zero wrench; so it is reset to the default. The child also
    dies with its parent."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    try:
        import ctypes

        ctypes.CDLL(None, use_errno=True).prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
    except Exception:  # noqa: BLE001 - not Linux: children simply outlive a killed bringup
        pass


def child_env() -> dict[str, str]:
    env = dict(os.environ, PYTHONUNBUFFERED="1")
    prefixes = [p for p in env.get("AMENT_PREFIX_PATH", "").split(os.pathsep) if p]
    if sys.prefix not in prefixes:  # the PyPI ROS wheels keep their message packages in the venv prefix
        env["AMENT_PREFIX_PATH"] = os.pathsep.join(prefixes + [sys.prefix])
    return env


class Bringup:
    """Runs the children until a signal (or a child's exit), then stops them in reverse order."""

    def __init__(self, specs: Iterable[ChildSpec], stop_timeout_s: float = STOP_TIMEOUT_S,
                 log: Optional[Callable[[str], None]] = None) -> None:
        self.specs = list(specs)
        self.stop_timeout_s = stop_timeout_s
        self.log: Callable[[str], None] = log or (lambda text: print(f"[bringup] {text}", file=sys.stderr, flush=True))
        self.procs: list[tuple[str, subprocess.Popen[bytes]]] = []  # (name, Popen) in start order
        self.signals = 0
        self.killed: list[str] = []

    def _on_signal(self, signum: int, _frame: Optional[FrameType]) -> None:
        self.signals += 1
        if self.signals == 1:
            self.log(f"{signal.Signals(signum).name}: stopping the nodes (again to kill them at once)")

    def start(self) -> None:
        env = child_env()
        for spec in self.specs:
            proc = subprocess.Popen(spec.argv, env=env, process_group=0, preexec_fn=_child_setup)
            self.procs.append((spec.name, proc))
            self.log(f"started {spec.name} (pid {proc.pid})")

    def stop(self) -> dict[str, int]:
        """Stop every child that still runs, last started first; returns {name: returncode}."""
        baseline = self.signals  # one more signal while stopping: kill the rest at once
        for name, proc in reversed(self.procs):
            if proc.poll() is not None:
                continue
            proc.send_signal(signal.SIGINT)
            deadline = time.monotonic() + self.stop_timeout_s
            while proc.poll() is None and time.monotonic() < deadline and self.signals == baseline:
                time.sleep(0.02)
            if proc.poll() is None:
                proc.kill()
                self.killed.append(name)
                self.log(f"{name} (pid {proc.pid}) did not stop: killed")
            proc.wait()
        return {name: proc.returncode for name, proc in self.procs}

    def run(self) -> int:
        previous = {s: signal.signal(s, self._on_signal) for s in (signal.SIGINT, signal.SIGTERM)}
        died: Optional[tuple[str, int]] = None
        try:
            self.start()
            while not self.signals and died is None:
                for name, proc in self.procs:
                    if proc.poll() is not None:
                        died = (name, proc.returncode)
                        break
                else:
                    time.sleep(0.05)
        finally:
            codes = self.stop()
            for s, handler in previous.items():
                signal.signal(s, handler)
        if died is not None:
            self.log(f"{died[0]} exited with code {died[1]}: stopped the others")
            return 1
        bad = {name: code for name, code in codes.items() if code != 0}
        if bad or self.killed:
            self.log(f"nodes ended with {bad} (killed: {self.killed})")
            return 1
        self.log("all nodes stopped")
        return 0


def bringup(backend: Optional[str] = None, port: Optional[str] = None, model: Optional[StrPath] = None,
            with_bridge: bool = False, record: Optional[StrPath] = None, namespace: str = contract.NAMESPACE,
            stop_timeout_s: float = STOP_TIMEOUT_S, dry_run: bool = False) -> int:
    """``polyforce bringup``: plan, print, run. Returns the exit code."""
    workdir = Path(tempfile.mkdtemp(prefix="polyforce-bringup-"))
    try:
        specs = plan(workdir, backend, port, model, with_bridge, record, namespace or contract.NAMESPACE)
        print(describe(specs), flush=True)
        if dry_run:
            return 0
        return Bringup(specs, stop_timeout_s).run()
    finally:
        shutil.rmtree(workdir, ignore_errors=True)
