"""The package type-checks and lints: mypy (pyproject.toml's [tool.mypy]) and ruff find no error.

CI runs ``make test``, so this is where the check is enforced (``make lint`` runs the same mypy).
mypy's cache goes to a temporary folder, so the repository stays clean; nothing is skipped: without
mypy installed (the ``dev`` extra) the test fails.
"""

import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _run_module(*args: str, timeout: float) -> subprocess.CompletedProcess:
    """``python -m ARGS`` in the repository, its output captured; fails at once when the tool is not installed."""
    out = subprocess.run([sys.executable, "-m", *args], cwd=ROOT, capture_output=True, text=True, timeout=timeout)
    assert f"No module named {args[0]}" not in out.stderr, f"{args[0]} is missing: pip install -e '.[dev]'"
    return out


@pytest.mark.slow
def test_mypy_finds_no_error():
    cache = Path(tempfile.gettempdir()) / "pasibot-mypy-cache"  # kept between runs: a warm check takes seconds
    out = _run_module("mypy", "--cache-dir", str(cache), "--config-file", str(ROOT / "pyproject.toml"), timeout=900)
    assert out.returncode == 0, out.stdout + out.stderr
    assert "Success: no issues found" in out.stdout, out.stdout


def test_ruff_finds_no_error():
    """``make lint``'s ruff check, enforced here too: the package, the tests and the benchmarks are ruff-clean."""
    out = _run_module("ruff", "check", "--no-cache", "pasibot_pin", "tests", "benchmarks", timeout=300)
    assert out.returncode == 0, out.stdout + out.stderr
