"""The package type-checks and lints: mypy (pyproject.toml's [tool.mypy]) and ruff find no error.

CI runs ``make test``, so this is where the check is enforced (``make lint`` runs the same mypy).
mypy's cache goes to a temporary folder, so the repository stays clean; nothing is skipped: without
mypy installed (the ``dev`` extra) the test fails.
"""

import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_mypy_finds_no_error():
    cache = Path(tempfile.gettempdir()) / "pasibot-mypy-cache"  # kept between runs: a warm check takes seconds
    out = subprocess.run(
        [sys.executable, "-m", "mypy", "--cache-dir", str(cache), "--config-file", str(ROOT / "pyproject.toml")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert "No module named mypy" not in out.stderr, "mypy is missing: pip install -e '.[dev]'"
    assert out.returncode == 0, out.stdout + out.stderr
    assert "Success: no issues found" in out.stdout, out.stdout


def test_ruff_finds_no_error():
    """``make lint``'s ruff check, enforced here too: the package, the tests and the benchmarks are ruff-clean."""
    out = subprocess.run(
        [sys.executable, "-m", "ruff", "check", "--no-cache", "pasibot_pin", "tests", "benchmarks"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert "No module named ruff" not in out.stderr, "ruff is missing: pip install -e '.[dev]'"
    assert out.returncode == 0, out.stdout + out.stderr
