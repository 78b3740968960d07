"""Habits that keep the code this way: lint, types, __all__ and docstrings of the ROS-free core."""
import ast
import os
import subprocess
import sys
from pathlib import Path

import pytest

from conftest import REPO

BIN = Path(sys.executable).parent
CORE = [*sorted((REPO / "polyforce_ros" / "physics").glob("[!_]*.py")),
        REPO / "polyforce_ros" / "runtime" / "compensator.py", REPO / "polyforce_ros" / "runtime" / "sources.py",
        *[REPO / "polyforce_ros" / f for f in ("record.py", "contract.py", "workflows.py", "model_file.py", "cdr.py",
                                                "serial_protocol.py", "haptics.py", "evaluation/latency.py")]]


def _run(*args):
    return subprocess.run([str(a) for a in args], cwd=REPO, capture_output=True, text=True, timeout=300)


def test_ruff_finds_no_errors():
    """ruff as an editor or pre-commit runs it: rules, line length and exceptions from pyproject.toml [tool.ruff]."""
    proc = _run(BIN / "ruff", "check")
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_mypy_checks_the_ros_free_core():
    proc = _run(BIN / "mypy")  # files and options: pyproject.toml [tool.mypy]
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_checks_are_configured_where_the_tools_look():
    """One home for the checkers' configuration (pyproject.toml), no build backend that would bypass setup.py."""
    import tomllib

    config = tomllib.loads((REPO / "pyproject.toml").read_text())
    assert "build-system" not in config and "project" not in config, "pyproject.toml is tool configuration only"
    assert config["tool"]["ruff"]["line-length"] == 130
    assert set(config["tool"]["ruff"]["lint"]["select"]) == {"F", "E", "W", "B"}
    assert config["tool"]["mypy"]["files"]
    assert "[mypy" not in (REPO / "setup.cfg").read_text(), "mypy's configuration lives in pyproject.toml only"
    ignored = (REPO / ".gitignore").read_text().split()
    assert {".ruff_cache/", ".mypy_cache/"} <= set(ignored)


@pytest.mark.parametrize("path", CORE, ids=lambda p: str(p.relative_to(REPO)))
def test_core_modules_declare_their_api_and_document_it(path):
    tree = ast.parse(path.read_text())
    exported = None
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "__all__" for t in node.targets):
            exported = {elt.value for elt in node.value.elts}
    assert exported is not None, f"{path.name} has no __all__"
    defined = {n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))}
    for node in tree.body:
        if isinstance(node, (ast.Assign, ast.AnnAssign)):
            for target in node.targets if isinstance(node, ast.Assign) else [node.target]:
                defined |= {t.id for t in ast.walk(target) if isinstance(t, ast.Name)}
    assert exported <= defined, f"{path.name}: __all__ names what it does not define: {sorted(exported - defined)}"
    undocumented = sorted(n.name for n in tree.body if isinstance(n, (ast.FunctionDef, ast.ClassDef))
                          and n.name in exported and not ast.get_docstring(n))
    assert not undocumented, f"{path.name}: public names without a docstring: {undocumented}"


def _undocumented_public_methods():
    out = set()
    for path in CORE:
        tree = ast.parse(path.read_text())
        exported = set()
        for node in tree.body:
            if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "__all__" for t in node.targets):
                exported = {elt.value for elt in node.value.elts}
        for node in tree.body:
            if isinstance(node, ast.ClassDef) and node.name in exported:
                out |= {f"{path.relative_to(REPO / 'polyforce_ros')}:{node.name}.{item.name}" for item in node.body
                        if isinstance(item, ast.FunctionDef) and not item.name.startswith("_")
                        and not ast.get_docstring(item)}
    return out


def test_undocumented_public_methods_only_shrink():
    """The methods of the core's public classes that lack a docstring are listed in test/undocumented_api.txt:
    a new one fails, and so does a listed one that has been documented since (the list must shrink with it)."""
    listed = {line.strip() for line in (REPO / "test" / "undocumented_api.txt").read_text().splitlines()
              if line.strip() and not line.startswith("#")}
    found = _undocumented_public_methods()
    assert not found - listed, f"public methods without a docstring: {sorted(found - listed)}"
    assert not listed - found, f"documented now, remove from test/undocumented_api.txt: {sorted(listed - found)}"


def test_the_unit_layer_needs_neither_rclpy_nor_a_process():
    """``pytest -m unit`` with rclpy unimportable and process start-up refused (conftest POLYFORCE_UNIT_GUARD)."""
    from conftest import LAYERS

    files = [f"test/{name}" for name in LAYERS["unit"]]
    proc = subprocess.run([sys.executable, "-m", "pytest", "-q", "-x", "-m", "unit", "-p", "no:cacheprovider", *files],
                          cwd=REPO, capture_output=True, text=True, timeout=900,
                          env={**os.environ, "POLYFORCE_UNIT_GUARD": "1"})
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-2000:]
