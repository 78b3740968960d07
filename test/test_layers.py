"""The package's rooms: layers only look down, ROS stays in the nodes, and no module takes another's private names."""
import ast
import subprocess
import sys
from pathlib import Path

from conftest import REPO

BIN = Path(sys.executable).parent


def test_the_import_contracts_hold():
    """``.importlinter``: layers only look down (imports inside functions included), rclpy only in the nodes."""
    proc = subprocess.run([str(BIN / "lint-imports")], cwd=REPO, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stdout[-4000:] + proc.stderr[-2000:]
    assert "BROKEN" not in proc.stdout and proc.stdout.count("KEPT") >= 3


def test_no_module_imports_a_private_name_of_another_module():
    offenders = []
    for path in sorted((REPO / "polyforce_ros").rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.ImportFrom) and node.module is not None:
                for alias in node.names:
                    if alias.name.startswith("_") and not alias.name.startswith("__"):
                        offenders.append(f"{path.relative_to(REPO)}:{node.lineno} imports {alias.name} from {node.module}")
    assert not offenders, "\n".join(offenders)


#: A module longer than this holds more than one concern: split it into a package by concern.
MAX_MODULE_LINES = 800


def test_no_module_is_longer_than_one_concern():
    long = {str(p.relative_to(REPO)): n for p in sorted((REPO / "polyforce_ros").rglob("*.py"))
            if (n := len(p.read_text().splitlines())) > MAX_MODULE_LINES}
    assert not long, f"modules over {MAX_MODULE_LINES} lines: {long}"
