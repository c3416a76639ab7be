"""Every unit of the package stays small enough to read: no module over 600 lines, no function over 80.

Read from the source with ``ast`` (methods and nested functions count as functions; a function's
length runs from its ``def`` line to its last line, docstring included, decorators not).
"""

from __future__ import annotations

import ast
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1] / "pasibot_pin"
MAX_MODULE_LINES = 600
MAX_FUNCTION_LINES = 80


def oversized(source: str, name: str, tree: ast.Module | None = None) -> list[str]:
    """One line per unit of ``source`` (a module called ``name``, parsed as ``tree`` if given) over its limit,
    naming it and its length."""
    found = []
    lines = len(source.splitlines())
    if lines > MAX_MODULE_LINES:
        found.append(f"{name}: {lines} lines (at most {MAX_MODULE_LINES})")

    def visit(node: ast.AST, prefix: str) -> None:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
                qualname = f"{prefix}{child.name}"
                length = (child.end_lineno or child.lineno) - child.lineno + 1
                if not isinstance(child, ast.ClassDef) and length > MAX_FUNCTION_LINES:
                    found.append(f"{name}:{child.lineno} {qualname}(): {length} lines (at most {MAX_FUNCTION_LINES})")
                visit(child, f"{qualname}.")
            else:
                visit(child, prefix)

    visit(tree if tree is not None else ast.parse(source), "")
    return found


def test_no_module_or_function_is_too_long(package_trees):
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        tree = package_trees[path.relative_to(PACKAGE).as_posix()]
        found += oversized(path.read_text(encoding="utf-8"), str(path.relative_to(PACKAGE.parent)), tree)
    assert not found, "split these:\n" + "\n".join(found)


def test_the_check_names_a_long_function_a_long_method_and_a_long_module():
    body = "".join(f"        x{k} = {k}\n" for k in range(MAX_FUNCTION_LINES))  # with its def: one line too many
    source = f"def short():\n    return 1\n\n\ndef long_one():\n{body}\n\nclass C:\n    def method(self):\n{body}"
    found = oversized(source, "synthetic.py")
    assert found == [
        f"synthetic.py:5 long_one(): {MAX_FUNCTION_LINES + 1} lines (at most {MAX_FUNCTION_LINES})",
        f"synthetic.py:{source.splitlines().index('    def method(self):') + 1} C.method(): "
        f"{MAX_FUNCTION_LINES + 1} lines (at most {MAX_FUNCTION_LINES})",
    ]
    just_right = "def f():\n" + "".join(f"    x{k} = {k}\n" for k in range(MAX_FUNCTION_LINES - 1))
    assert oversized(just_right, "ok.py") == []
    long_module = "x = 1\n" * (MAX_MODULE_LINES + 1)
    assert oversized(long_module, "big.py") == [f"big.py: {MAX_MODULE_LINES + 1} lines (at most {MAX_MODULE_LINES})"]
    assert oversized("x = 1\n" * MAX_MODULE_LINES, "fits.py") == []
