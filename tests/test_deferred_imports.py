"""Function-level imports: each one stays only where it keeps the CLI's start fast, and says so.

An import inside a function carries a trailing comment in one of the forms of :data:`REASON`:

* ``# deferred: optional extra (mujoco)``: a package of an extra (``[mujoco]``, ``[sweep]``);
* ``# deferred: heavy (matplotlib), keeps the CLI's start fast``: a slow package (or a module of
  ours that imports one) that ``pasibot --help`` and the commands that do not use it never load;
* ``# deferred: keeps the CLI's start fast``: a module of ours that the modules ``pasibot`` loads
  at its start (``pasibot_pin.cli.*`` and what they import) would otherwise load for every command;
* ``# deferred: import cycle (MODULE imports this module)``: the two modules need each other.

Any other import belongs at the top of its module. The comment may sit on any line of the
statement (a parenthesised import carries it after its ``(``).
"""

from __future__ import annotations

import ast
import io
import re
import subprocess
import sys
import tokenize
from pathlib import Path

import pytest

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "pasibot_pin"

REASON = re.compile(
    r"# deferred: (?:optional extra \([\w.]+\)|heavy \([\w.]+\), keeps the CLI's start fast"
    r"|keeps the CLI's start fast|import cycle \([\w.]+ imports this module\))"
)
"""The trailing comment of a function-level import (the whole comment)."""

KNOWN_UNCOMMENTED: set[str] = set()
"""Files whose function-level imports are not yet sorted out (moved up or commented): empty it as they are.
A file listed here that no longer needs to be fails :func:`test_the_known_exceptions_are_still_needed`."""

HEAVY = (
    "matplotlib",
    "mujoco",
    "dask",
    "distributed",
    "optuna",
    "pyarrow",
    "scipy",
    "tqdm",
    "meshcat",
    "yourdfpy",
    "trimesh",
    "PIL",
    "xacro",
    "zmq",
)
"""Packages ``pasibot --help`` must not import: optional extras, or slow to import."""


def function_level_imports(source: str) -> list[tuple[int, str, str]]:
    """(line, statement, its comments) of every import inside a function of ``source``."""
    comments: dict[int, list[str]] = {}
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type == tokenize.COMMENT:
            comments.setdefault(token.start[0], []).append(token.string)
    found = []

    def visit(node: ast.AST, in_function: bool) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef)):
                visit(child, True)
            elif isinstance(child, (ast.Import, ast.ImportFrom)) and in_function:
                end = child.end_lineno or child.lineno
                text = " ".join(c for line in range(child.lineno, end + 1) for c in comments.get(line, []))
                found.append((child.lineno, ast.unparse(child), text))
            else:
                visit(child, in_function)

    visit(ast.parse(source), False)
    return found


def uncommented(source: str, name: str) -> list[str]:
    """``name:line statement`` of each function-level import of ``source`` without a :data:`REASON` comment."""
    return [
        f"{name}:{line} {statement}"
        for line, statement, comment in function_level_imports(source)
        if not REASON.fullmatch(comment.strip())
    ]


def package_files() -> dict[str, str]:
    return {str(p.relative_to(ROOT)): p.read_text(encoding="utf-8") for p in sorted(PACKAGE.rglob("*.py"))}


@pytest.mark.slow
def test_every_function_level_import_says_why_it_is_deferred():
    missing = []
    for name, source in package_files().items():
        if name not in KNOWN_UNCOMMENTED:
            missing += uncommented(source, name)
    assert not missing, "move these to the top of their module, or say why they stay (REASON):\n" + "\n".join(missing)


def test_the_known_exceptions_are_still_needed():
    files = package_files()
    assert KNOWN_UNCOMMENTED <= set(files), sorted(KNOWN_UNCOMMENTED - set(files))
    stale = [name for name in sorted(KNOWN_UNCOMMENTED) if not uncommented(files[name], name)]
    assert not stale, f"every function-level import of these says why: remove them from KNOWN_UNCOMMENTED: {stale}"


def test_the_check_sees_a_bare_or_vague_comment_and_accepts_each_reason():
    source = """
import json


def f():
    import math
    from os import path  # for speed
    import matplotlib.pyplot as plt  # deferred: heavy (matplotlib), keeps the CLI's start fast
    import mujoco  # deferred: optional extra (mujoco)
    from pasibot_pin.jobs import run_jobs  # deferred: keeps the CLI's start fast
    from pasibot_pin.report import answers  # deferred: import cycle (pasibot_pin.report.answers imports this module)
    from pasibot_pin.viz.plots import (  # deferred: heavy (matplotlib), keeps the CLI's start fast
        plot_robot,
    )

    class Inner:
        def method(self):
            import csv

    return json, math, path, plt, mujoco, run_jobs, answers, plot_robot, Inner
"""
    assert uncommented(source, "m.py") == ["m.py:6 import math", "m.py:7 from os import path", "m.py:18 import csv"]


def test_pasibot_help_imports_no_heavy_package():
    """The console script (pyproject's [project.scripts]) run as ``pasibot --help`` loads none of :data:`HEAVY`."""
    module, function = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]["pasibot"].split(":")
    code = (
        "import importlib, sys\n"
        "sys.argv = ['pasibot', '--help']\n"
        "try:\n"
        f"    getattr(importlib.import_module({module!r}), {function!r})()\n"
        "except SystemExit:\n"
        "    pass\n"
        f"print('HEAVY', sorted({{name.split('.')[0] for name in sys.modules}} & set({HEAVY!r})))\n"
    )
    out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, check=True, capture_output=True, text=True).stdout
    assert "usage: pasibot" in out
    assert out.strip().splitlines()[-1] == "HEAVY []"
