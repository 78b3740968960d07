"""Habits that keep the code this way: lint, types, __all__ and docstrings of the ROS-free core."""
import ast
import io
import os
import re
import subprocess
import sys
import tokenize
from pathlib import Path

import pytest

from conftest import REPO

BIN = Path(sys.executable).parent
CORE = [*sorted((REPO / "polyforce_ros" / "physics").rglob("[!_]*.py")),
        REPO / "polyforce_ros" / "runtime" / "compensator.py", REPO / "polyforce_ros" / "runtime" / "sources.py",
        *sorted((REPO / "polyforce_ros").glob("**/cdr.py")),
        *[REPO / "polyforce_ros" / f for f in ("record.py", "contract.py", "workflows.py", "model_file.py",
                                                "serial_protocol.py", "haptics.py", "evaluation/latency.py")]]


def _run(*args):
    return subprocess.run([str(a) for a in args], cwd=REPO, capture_output=True, text=True, timeout=300)


def test_ruff_finds_no_errors():
    """ruff as an editor or pre-commit runs it: rules, line length and exceptions from pyproject.toml [tool.ruff]."""
    proc = _run(BIN / "ruff", "check")
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_mypy_strict_checks_the_whole_package():
    proc = _run(BIN / "mypy")  # files and options: pyproject.toml [tool.mypy]
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_checks_are_configured_where_the_tools_look():
    """One home for the checkers' configuration (pyproject.toml), no build backend that would bypass setup.py."""
    import tomllib

    config = tomllib.loads((REPO / "pyproject.toml").read_text())
    assert "build-system" not in config and "project" not in config, "pyproject.toml is tool configuration only"
    assert config["tool"]["ruff"]["line-length"] == 130
    assert set(config["tool"]["ruff"]["lint"]["select"]) == {"F", "E", "W", "B"}
    assert config["tool"]["mypy"]["files"] == ["polyforce_ros"] and config["tool"]["mypy"]["strict"] is True
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


# ---------------------------------------------------------------- no development narration
#: Words that narrate how the code was developed rather than what it does: numbered rounds or sessions of work,
#: reviews, the discrepancy bench's tuning history, issue numbers, past states ("had been", "(was ...)").
#: The history belongs in CHANGELOG.md and git, not in the README, the docs, comments or docstrings.
NARRATION = re.compile(
    r"tune[- ]split"
    r"|\breview(s|ed|er|ers)?\b"
    r"|\brounds? of (work|development|changes)\b"
    r"|\b(first|second|third|fourth|fifth|sixth|seventh|eighth|ninth|tenth|\d+(st|nd|rd|th)|this|that|previous|last"
    r"|earlier|next)\s+(round|session)\b"
    r"|\bsession of \d{4}"
    r"|\bissues? \d+"
    r"|(?<![\w&#/])#\d+\b"
    r"|\bhad been\b"
    r"|\(was\b",
    re.IGNORECASE)

def _comments_and_docstrings(path):
    """(line, text) of every comment and every module, class and function docstring line of a Python file."""
    source = path.read_text()
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.COMMENT:
            yield tok.start[0], tok.string
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)) and node.body:
            first = node.body[0]
            if isinstance(first, ast.Expr) and isinstance(first.value, ast.Constant) and isinstance(first.value.value, str):
                for i, line in enumerate(first.value.value.splitlines()):
                    yield first.value.lineno + i, line


def _narration(lines):
    return [f"{number}: [{match.group(0)}] {text.strip()[:120]}"
            for number, text in lines for match in NARRATION.finditer(text)]


def _narration_targets():
    docs = [REPO / "README.md", *sorted((REPO / "docs").rglob("*.md"))]
    code = [*sorted((REPO / "polyforce_ros").rglob("*.py")), *sorted((REPO / "bench").glob("*.py"))]
    for path in docs + code:
        yield pytest.param(path, id=str(path.relative_to(REPO)))


def test_narration_finder_finds_narration():
    """The check can fail: it finds the kinds of sentence it is for and passes product descriptions."""
    narrated = ["tune split 53/59 -> 56/59", "found by the review", "the seventh session's figures", "see issue 28",
                "fixed in #12", "the floor had been overestimated", "a partial fit must explain 80 % (was 60 %)",
                "Third session (2026-11-23)", "after two rounds of work"]
    plain = ["the tune and held-out splits", "what came before activation is not its history", "a 30 s run",
             "each settling round refits the core", "colour #1f77b4", "10 interleaved rounds of 20 s"]
    assert all(_narration([(1, text)]) for text in narrated), [t for t in narrated if not _narration([(1, t)])]
    assert not _narration([(i, text) for i, text in enumerate(plain)])


@pytest.mark.parametrize("path", list(_narration_targets()))
def test_docs_and_code_describe_the_product_not_its_development(path):
    """README.md, docs/ and the comments and docstrings of polyforce_ros/ and bench/ say what the product does;
    history goes to CHANGELOG.md. The failure lists every line (file:line) that narrates."""
    if path.suffix == ".md":
        lines = enumerate(path.read_text().splitlines(), start=1)
    else:
        lines = _comments_and_docstrings(path)
    found = _narration(lines)
    rel = path.relative_to(REPO)
    assert not found, f"{rel} narrates its development:\n" + "\n".join(f"{rel}:{line}" for line in found)
