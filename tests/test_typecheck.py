"""The package type-checks: mypy, with the settings of pyproject.toml's [tool.mypy], finds no error.

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
