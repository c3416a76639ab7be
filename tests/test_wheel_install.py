"""A plain ``pip install`` of the wheel (no extras, a clean venv) runs every command from any folder.

The wheel is built from this checkout (``pip wheel --no-deps``, hatchling from PyPI) and installed
into a fresh ``python -m venv --without-pip`` (no system site-packages) by this venv's pip (``pip --python``); its
base dependencies come from PyPI.
The venv is cached between runs beside pytest's numbered temporary folders, keyed by the base
dependencies and the Python version; the wheel itself is built every run and reinstalled unless
the venv already holds exactly its files (:func:`_holds`: a run from unchanged sources). Each command's
smallest invocation runs in a temporary folder outside the repository, with no ``PYTHONPATH``:
only the installed package can answer. ``sweep`` and ``optimize`` need the ``[sweep]`` extra and
must say so in one line, before any work, leaving no file. ``analyze`` (the longest, ~30 s) is
started in the background as soon as the venv is ready.

``--help``, ``info``, ``analyze`` and the ``[sweep]`` refusals run as ``pasibot`` processes, the
installed console script itself. The other commands, whose work outweighs their start, run one
after the other in a single process of the venv's Python (:data:`RUNNER`), each as the console
script runs it (``sys.argv`` set, ``main()``), with its own stdout, stderr and exit code: one
start of Pinocchio, NumPy and Matplotlib (~2 s) instead of one per command.
"""

from __future__ import annotations

import fcntl
import hashlib
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

try:
    import tomllib
except ModuleNotFoundError:  # Python 3.10
    import tomli as tomllib

ROOT = Path(__file__).resolve().parents[1]
TIMES: dict[str, float] = {}
"""Wall time of each step [s], printed at the end of the module (``-s`` or the captured output)."""


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


def _clean_env(venv: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONHOME", "VIRTUAL_ENV", "PYTHONSTARTUP")}
    env["PATH"] = f"{venv / 'bin'}{os.pathsep}{env.get('PATH', '')}"
    env["MPLBACKEND"] = "Agg"
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    return env


def _timed(name: str, args: list, **kwargs) -> subprocess.CompletedProcess:
    start = time.monotonic()
    done = subprocess.run(args, capture_output=True, text=True, **kwargs)
    done.seconds = TIMES[name] = time.monotonic() - start
    return done


def _holds(venv: Path, wheel: Path) -> bool:
    """Whether ``venv`` has ``wheel`` installed and nothing else of the package: the same files as the wheel's
    RECORD, each with its SHA-256, and the ``pasibot`` script (pip's own files and byte code aside)."""
    import base64
    import zipfile

    with zipfile.ZipFile(wheel) as archive:
        name = next(n for n in archive.namelist() if n.endswith(".dist-info/RECORD"))
        wanted = [line.rsplit(",", 2)[:2] for line in archive.read(name).decode().splitlines() if line]
    sites = list(venv.glob("lib/python*/site-packages"))
    if len(sites) != 1 or not (sites[0] / name).is_file() or not (venv / "bin" / "pasibot").is_file():
        return False
    site, pip_own = sites[0], {f"{name.split('/')[0]}/{f}" for f in ("INSTALLER", "REQUESTED", "direct_url.json")}
    installed = {line.split(",", 1)[0] for line in (site / name).read_text().splitlines() if line}
    installed = {p for p in installed if not p.startswith("../") and "__pycache__" not in p} - pip_own
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
        return _timed(name, [str(self.venv / "bin" / "pasibot"), *args], cwd=self.work, env=self.env, timeout=timeout)

    def start(self, *args: str) -> subprocess.Popen:
        return subprocess.Popen(
            [str(self.venv / "bin" / "pasibot"), *args],
            cwd=self.work,
            env=self.env,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )


@pytest.fixture(scope="module")
def installed(tmp_path_factory) -> Installed:
    dist = tmp_path_factory.mktemp("dist")
    built = _timed("pip wheel", [sys.executable, "-m", "pip", "wheel", "--no-deps", "-q", "-w", str(dist), str(ROOT)])
    assert built.returncode == 0, built.stderr
    (wheel,) = dist.glob("pasibot_pin-*.whl")
    cache = _cache_root(tmp_path_factory)
    venv = cache / f"pasibot-wheel-venv-{_key()}"
    with open(cache / f"{venv.name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)  # another worker or run may be building the same venv
        # this venv's pip installs into the plain venv (pip --python): the plain venv needs no pip of its own, and
        # --no-compile leaves the byte code to the first import (pip's compiling of every installed module, unused
        # ones included, was ~45 of its ~80 s)
        pip = [sys.executable, "-m", "pip", "--python", str(venv / "bin" / "python"), "install", "-q", "--no-compile"]
        env = _clean_env(venv)
        if not (venv / ".complete").is_file():
            shutil.rmtree(venv, ignore_errors=True)
            made = _timed("venv", [sys.executable, "-m", "venv", "--without-pip", str(venv)], env=env)
            assert made.returncode == 0, made.stderr
            done = _timed("pip install (base deps from PyPI)", [*pip, str(wheel)], env=env, timeout=1200)
            assert done.returncode == 0, done.stderr
            (venv / ".complete").touch()
        elif not _holds(venv, wheel):
            done = _timed(
                "pip install (wheel only, cached venv)", [*pip, "--no-deps", "--force-reinstall", str(wheel)], env=env
            )
            assert done.returncode == 0, done.stderr
        assert _holds(venv, wheel)
    work = tmp_path_factory.mktemp("outside")
    assert ROOT not in work.parents
    yield Installed(venv, work)
    print("\nwheel install timings [s]: " + ", ".join(f"{k} {v:.1f}" for k, v in TIMES.items()))


@pytest.fixture(scope="module")
def analyze(installed):
    """``pasibot analyze`` running in the background from the moment the venv is ready."""
    start = time.monotonic()
    proc = installed.start("analyze", "--out", "report")
    yield proc, start
    if proc.poll() is None:
        proc.kill()
        proc.communicate()


def test_plain_venv_has_no_extras_and_imports_the_wheel(installed, analyze):
    code = (
        "import importlib.util, pasibot_pin; print(pasibot_pin.__file__); "
        "print([m for m in ('pyarrow', 'optuna', 'tqdm', 'distributed', 'mujoco') "
        "if importlib.util.find_spec(m)])"
    )
    done = subprocess.run(
        [str(installed.venv / "bin" / "python"), "-c", code],
        cwd=installed.work,
        env=installed.env,
        capture_output=True,
        text=True,
    )
    assert done.returncode == 0, done.stderr
    location, extras = done.stdout.splitlines()
    assert Path(location).resolve().is_relative_to(installed.venv.resolve())
    assert extras == "[]"  # a clean venv: none of the extras' modules
    assert not list(installed.venv.glob("lib/*/site-packages/docs"))  # the wheel installs no top-level docs/
    packaged = Path(location).parent
    for name in (
        "urdf/pasibot.urdf.xacro",
        "urdf/macros.urdf.xacro",
        "urdf/pasibot_spring_2leg.urdf",
        "results/answers_summary.json",
        "results/least_torque_seed_stride.toml",
    ):
        assert (packaged / name).is_file(), name


COMMANDS = [
    ("--help",),
    ("info",),
    ("gait", "--steps", "1", "--step-deg", "30", "--out", "gait"),
    ("torques", "--samples", "5", "--out", "torques"),
    ("contact", "--samples", "5", "--out", "contact"),
    ("energy", "--omegas", "1", "--variants", "spring", "--nodes", "8", "--out", "energy"),
    ("build-urdf", "--defaults", "--out", "urdf"),
    ("export-mjcf", "--out", "robot.xml"),
    ("export-html", "--steps", "1", "--samples-per-step", "4", "--out", "gait.html"),
    ("view", "--steps", "1", "--samples-per-step", "3", "--fps", "60"),
    ("simulate", "--ground", "weld", "--steps", "1", "--no-cases", "--out", "sim"),
]
pytestmark = [pytest.mark.integration, pytest.mark.slow]

OWN_PROCESS = {("--help",), ("info",)}
"""Commands run as their own ``pasibot`` process; the others share one process (:func:`batch`)."""

RUNNER = r"""
import json, os, sys, time, traceback
if sys.path[0] == "":  # python -c puts the working folder first; the console script does not
    del sys.path[0]
import pasibot_pin
from pasibot_pin.__main__ import main

results = []
argvs, logs = json.loads(sys.argv[1]), sys.argv[2]
for k, argv in enumerate(argvs):
    out, err = os.path.join(logs, f"{k}.out"), os.path.join(logs, f"{k}.err")
    sys.stdout.flush(), sys.stderr.flush()
    saved = os.dup(1), os.dup(2)
    with open(out, "w") as o, open(err, "w") as e:
        os.dup2(o.fileno(), 1), os.dup2(e.fileno(), 2)  # the file descriptors: a child's output too
        sys.argv = ["pasibot", *argv]  # what the console script runs: sys.exit(main())
        start = time.monotonic()
        try:
            code = main()
        except SystemExit as stop:
            code = stop.code if isinstance(stop.code, int) else (0 if stop.code is None else 1)
        except BaseException:
            traceback.print_exc()
            code = 1
        seconds = time.monotonic() - start
        sys.stdout.flush(), sys.stderr.flush()
        os.dup2(saved[0], 1), os.dup2(saved[1], 2)
    os.close(saved[0]), os.close(saved[1])
    results.append({"argv": argv, "returncode": code, "seconds": seconds, "stdout": out, "stderr": err})
print(json.dumps({"package": pasibot_pin.__file__, "results": results}))
"""
"""The venv's Python runs this with the commands' argv lists (JSON) and a folder for their outputs: each one as
``pasibot ARGV`` runs, in turn, in the working folder; its stdout and stderr (file descriptors 1 and 2, so a
child process's output too) into files of that folder."""


@pytest.fixture(scope="module")
def batch(installed, tmp_path_factory) -> dict[tuple[str, ...], subprocess.CompletedProcess]:
    """The commands not in :data:`OWN_PROCESS`, run in one process of the venv's Python (:data:`RUNNER`)."""
    argvs = [list(args) for args in COMMANDS if args not in OWN_PROCESS]
    logs = tmp_path_factory.mktemp("batch")
    python = str(installed.venv / "bin" / "python")
    command = [python, "-c", RUNNER, json.dumps(argvs), str(logs)]
    done = _timed("batch of commands", command, cwd=installed.work, env=installed.env, timeout=600)
    assert done.returncode == 0, done.stderr
    report = json.loads(done.stdout.splitlines()[-1])
    assert Path(report["package"]).resolve().is_relative_to(installed.venv.resolve())  # the installed wheel
    out = {}
    for result in report["results"]:
        TIMES[" ".join(result["argv"])] = result["seconds"]
        stdout, stderr = Path(result["stdout"]).read_text(), Path(result["stderr"]).read_text()
        out[tuple(result["argv"])] = subprocess.CompletedProcess(result["argv"], result["returncode"], stdout, stderr)
    return out


@pytest.mark.parametrize("args", COMMANDS, ids=lambda a: "-".join(a[:2]))
def test_command_runs_on_the_plain_install(installed, analyze, batch, args):
    done = installed.run(*args) if args in OWN_PROCESS else batch[args]
    assert done.returncode == 0, done.stderr
    assert "Traceback" not in done.stderr
    target = args[args.index("--out") + 1] if "--out" in args else None
    if target is not None:
        path = installed.work / target
        assert path.exists(), args
        if path.is_dir():
            assert any(path.iterdir())
        else:
            assert path.stat().st_size > 0
    else:
        assert done.stdout.strip()


@pytest.mark.parametrize("command", ["sweep", "optimize"])
@pytest.mark.parametrize("dask", [[], ["--dask", "local"]], ids=["pool", "dask"])
def test_sweep_commands_name_their_extra_in_one_line_and_write_nothing(installed, analyze, command, dask):
    out = installed.work / f"{command}-{len(dask)}"
    extra = ["--n", "2"] if command == "sweep" else ["--trials", "2"]
    done = installed.run(command, "--out", str(out), *extra, *dask, timeout=60)
    assert done.returncode == 2
    lines = done.stderr.strip().splitlines()
    assert len(lines) == 1, done.stderr
    assert lines[0].startswith(f"pasibot {command}: error: ")
    assert "[sweep] extra" in lines[0] and "pip install 'pasibot-pin[sweep]'" in lines[0]
    assert done.seconds < 20  # before any work
    assert not out.exists()


def test_analyze_writes_the_report(installed, analyze):
    proc, start = analyze
    out, err = proc.communicate(timeout=600)
    TIMES["analyze (background)"] = time.monotonic() - start
    assert proc.returncode == 0, err
    assert "Traceback" not in err
    report = installed.work / "report" / "report.md"
    text = report.read_text()
    assert "## Design exploration" in text
    summary = json.loads((ROOT / "docs" / "results" / "answers_summary.json").read_text())
    assert f"({summary['floor']['trials']} designs)" in text  # read from the packaged summary
