"""The plain install, shared by the tests that need it: this checkout's wheel in a clean venv (no extras), and
``pasibot analyze`` run there once.

The wheel is built from this checkout (``pip wheel --no-deps --no-build-isolation``: the dev extra's hatchling)
and installed into a fresh ``python -m venv --without-pip`` (no system site-packages) by this venv's uv
(``uv pip install --python``, the installer ``make install`` uses); its base dependencies come from PyPI, through
uv's cache. A user's ``pip install .`` resolves the same metadata (the README's); uv does it in seconds.
The venv is cached between runs beside pytest's numbered temporary folders, keyed by the base
dependencies and the Python version; the wheel itself is built every run and reinstalled unless
the venv already holds exactly its files (:func:`_holds`: a run from unchanged sources). Commands run
in a temporary folder outside the repository, with no ``PYTHONPATH``: only the installed package can answer.

``analyze`` (the main job, ``make demo``'s; the longest, ~20 s on 2 processes) is started in the background as soon
as the venv is ready, and its report (:class:`Analyzed`) is what the report tests read: the sections as a user's
install writes them, not a second computation of them in the tests' own process.

The fixtures are session-scoped and ``conftest.py`` imports them. Every test using :func:`installed` carries the
xdist group :data:`GROUP` (``conftest.py``), so that under ``--dist loadgroup`` one worker builds the venv and
runs ``analyze`` once for all of them.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import re
import shutil
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import pytest

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

GROUP = "plain_install"
"""The xdist group of every test that uses the plain install (``conftest.py`` adds it)."""

ROOT = Path(__file__).resolve().parents[1]
INSTALLER_FILES = ("INSTALLER", "REQUESTED", "direct_url.json", "uv_cache.json")
"""What the installer (uv; pip writes the first three) adds to the wheel's ``.dist-info``."""
TIMES: dict[str, float] = {}
"""Wall time of each step [s], printed when the session ends (``-s`` or the captured output)."""


def _cache_root(tmp_path_factory) -> Path:
    """pytest's ``pytest-of-USER`` folder (kept across runs), or the base temp folder if there is none."""
    base = tmp_path_factory.getbasetemp()
    for folder in (base, *base.parents):
        if folder.name.startswith("pytest-of-"):
            return folder
    return base


def _key() -> str:
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    text = json.dumps([project["dependencies"], project["requires-python"], sys.version, sys.platform])
    return hashlib.sha256(text.encode()).hexdigest()[:12]


def _uv() -> str:
    """The ``uv`` executable of this venv (the dev extra), or the test fails naming the extra."""
    try:
        from uv import find_uv_bin
    except ImportError:
        pytest.fail("uv is missing: pip install -e '.[dev]'")
    return find_uv_bin()


def _clean_env(venv: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV", "PYTHONSTARTUP")}
    env["PATH"] = f"{venv / 'bin'}{os.pathsep}{env.get('PATH', '')}"
    env["MPLBACKEND"] = "Agg"
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    return env


def timed(name: str, args: list, **kwargs) -> subprocess.CompletedProcess:
    start = time.monotonic()
    done = subprocess.run(args, capture_output=True, text=True, **kwargs)
    done.seconds = TIMES[name] = time.monotonic() - start
    return done


def _holds(venv: Path, wheel: Path) -> bool:
    """Whether ``venv`` has ``wheel`` installed and nothing else of the package: the same files as the wheel's
    RECORD, each with its SHA-256, and the ``pasibot`` script (the installer's own files and byte code aside)."""
    import base64
    import zipfile

    with zipfile.ZipFile(wheel) as archive:
        name = next(n for n in archive.namelist() if n.endswith(".dist-info/RECORD"))
        wanted = [line.rsplit(",", 2)[:2] for line in archive.read(name).decode().splitlines() if line]
    sites = list(venv.glob("lib/python*/site-packages"))
    if len(sites) != 1 or not (sites[0] / name).is_file() or not (venv / "bin" / "pasibot").is_file():
        return False
    site, own = sites[0], {f"{name.split('/')[0]}/{f}" for f in INSTALLER_FILES}
    installed = {line.split(",", 1)[0] for line in (site / name).read_text().splitlines() if line}
    installed = {p for p in installed if not p.startswith("../") and "__pycache__" not in p} - own
    if installed != {path for path, _ in wanted}:
        return False
    for path, digest in wanted:
        if digest:  # the RECORD itself has none
            algorithm, value = digest.split("=", 1)
            actual = hashlib.new(algorithm, (site / path).read_bytes()).digest()
            if base64.urlsafe_b64encode(actual).rstrip(b"=").decode() != value:
                return False
    return True


class Installed:
    """The venv with the wheel installed, and where the commands run."""

    def __init__(self, venv: Path, work: Path):
        self.venv, self.work, self.env = venv, work, _clean_env(venv)

    def run(self, *args: str, timeout: float = 300) -> subprocess.CompletedProcess:
        name = " ".join(a for a in args if not a.startswith("/"))
        return timed(name, [str(self.venv / "bin" / "pasibot"), *args], cwd=self.work, env=self.env, timeout=timeout)

    def start(self, *args: str) -> subprocess.Popen:
        return subprocess.Popen(
            [str(self.venv / "bin" / "pasibot"), *args],
            cwd=self.work,
            env=self.env,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )


@pytest.fixture(scope="session")
def installed(tmp_path_factory) -> Installed:
    dist = tmp_path_factory.mktemp("dist")
    # hatchling from this venv (the dev extra), not a build environment made and filled for every run (~3 s)
    wheel_cmd = [sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w", str(dist)]
    built = timed("pip wheel", [*wheel_cmd, str(ROOT)])
    assert built.returncode == 0, built.stderr
    (wheel,) = dist.glob("pasibot_pin-*.whl")
    cache = _cache_root(tmp_path_factory)
    venv = cache / f"pasibot-wheel-venv-{_key()}"
    with open(cache / f"{venv.name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # another worker or run may be building the same venv
        # this venv's uv (the dev extra; what `make install` ran) installs into the plain venv: the plain venv needs no
        # installer of its own, the wheels come from uv's cache when `make install` filled it (~3 s, where pip took
        # ~20 s of CPU), and no byte code is compiled ahead (the first import compiles what it uses)
        install = [_uv(), "pip", "install", "--python", str(venv / "bin" / "python"), "--quiet"]
        env = _clean_env(venv)
        if not (venv / ".complete").is_file():
            shutil.rmtree(venv, ignore_errors=True)
            made = timed("venv", [sys.executable, "-m", "venv", "--without-pip", str(venv)], env=env)
            assert made.returncode == 0, made.stderr
            done = timed("uv pip install (base deps from PyPI)", [*install, str(wheel)], env=env, timeout=1200)
            assert done.returncode == 0, done.stderr
            (venv / ".complete").touch()
        elif not _holds(venv, wheel):
            done = timed(
                "uv pip install (wheel only, cached venv)", [*install, "--no-deps", "--reinstall", str(wheel)], env=env
            )
            assert done.returncode == 0, done.stderr
        assert _holds(venv, wheel)
    work = tmp_path_factory.mktemp("outside")
    assert ROOT not in work.parents
    yield Installed(venv, work)
    print("\nwheel install timings [s]: " + ", ".join(f"{k} {v:.1f}" for k, v in TIMES.items()))


@pytest.fixture(scope="session")
def analyze(installed):
    """``pasibot analyze`` running in the background from the moment the venv is ready: (process, start [s])."""
    start = time.monotonic()
    proc = installed.start("analyze", "--out", "report")
    yield proc, start
    if proc.poll() is None:
        proc.kill()
        proc.communicate()


@dataclass(frozen=True)
class Analyzed:
    """What ``pasibot analyze --out report`` wrote in the plain install.

    Attributes:
        folder: the output folder.
        text: its ``report.md``.

    """

    folder: Path
    text: str

    def section(self, heading: str) -> str:
        """The section whose ``## `` heading starts with ``heading``: from its heading to the next one."""
        found = re.findall(rf"^## {re.escape(heading)}.*?(?=^## |\Z)", self.text, re.M | re.S)
        assert len(found) == 1, f"{len(found)} sections headed {heading!r}"
        return found[0]


@pytest.fixture(scope="session")
def analyzed(installed, analyze) -> Analyzed:
    """The plain install's report, once ``analyze`` has finished (and succeeded, with no traceback)."""
    proc, start = analyze
    _, err = proc.communicate(timeout=600)
    TIMES["analyze (background)"] = time.monotonic() - start
    assert proc.returncode == 0, err
    assert "Traceback" not in err
    folder = installed.work / "report"
    return Analyzed(folder, (folder / "report.md").read_text(encoding="utf-8"))
