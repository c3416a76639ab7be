"""A plain ``pip install`` of the wheel (no extras, a clean venv) runs every command from any folder.

The install and ``analyze``'s run in it are :mod:`plain_install`'s session fixtures (the report tests read the
same report). Each command's smallest invocation runs in a temporary folder outside the repository, with no
``PYTHONPATH``: only the installed package can answer. ``sweep`` and ``optimize`` need the ``[sweep]`` extra and
must say so in one line, before any work, leaving no file.

``--help``, ``info``, ``analyze`` and the ``[sweep]`` refusals run as ``pasibot`` processes, the
installed console script itself. The other commands, whose work outweighs their start, run one
after the other in a single process of the venv's Python (:data:`RUNNER`), each as the console
script runs it (``sys.argv`` set, ``main()``), with its own stdout, stderr and exit code: one
start of Pinocchio, NumPy and Matplotlib (~2 s) instead of one per command.
"""

from __future__ import annotations

import json
import subprocess
from pathlib import Path

import pytest
from plain_install import ROOT, TIMES, timed


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
    done = timed("batch of commands", command, cwd=installed.work, env=installed.env, timeout=600)
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


def test_analyze_writes_the_report(analyzed):
    text = analyzed.text
    assert "## Design exploration" in text
    summary = json.loads((ROOT / "docs" / "results" / "answers_summary.json").read_text())
    assert f"({summary['floor']['trials']} designs)" in text  # read from the packaged summary
