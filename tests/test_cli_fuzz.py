"""Issue 24's fuzz: every hostile value of every numeric flag is one line naming the flag, before any work.

Hostile values (huge, tiny, NaN, infinite, negative, zero, of the wrong type, empty) are tried on
every numeric flag of every command, read from ``pasibot``'s own parser, so a flag added later is
fuzzed too (and must get a bound in :data:`pasibot_pin.cli.bounds.BOUNDS`). A value the bound
accepts is not run (that would be real work); every other one must end with exit code 2, one
line ``pasibot CMD: error: ...`` naming the flag and its range, and no file. Then the fuzz's
own findings, one test each, and the data-safety rules of ``--force`` and the output folders.
"""

from __future__ import annotations

import argparse
import math
import os
import re
from pathlib import Path

import pytest

from pasibot_pin.__main__ import build_parser, main
from pasibot_pin.cli.bounds import BOUNDS, Bound
from pasibot_pin.cli.common import float_list
from pasibot_pin.model.design import SPECS

HOSTILE = ["1e300", "1e-300", "nan", "inf", "-inf", "-1e300", "-1", "0", "1000000000", "abc", "", "0.5"]
"""Values tried on every numeric flag (as typed on the command line)."""

REQUIRED = {
    "sweep": ["--out", "{tmp}/run"],
    "optimize": ["--out", "{tmp}/run"],
    "export-mjcf": ["--out", "{tmp}/a.xml"],
    "find-walker": ["--out", "{tmp}/w.toml"],
}
"""Flags a command needs besides the fuzzed one (none of them is written: the checks come first)."""


def _subparsers() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(action.choices)


def _numeric_actions() -> list[tuple[str, argparse.Action]]:
    out = []
    for command, sub in _subparsers().items():
        for action in sub._actions:
            if action.type in (int, float, float_list):
                out.append((command, action))
    return out


def _parsed(action: argparse.Action, text: str):
    """The value argparse makes of ``text``, or ``None`` when it cannot read it."""
    try:
        if action.type is float_list:
            return float_list(text)
        return action.type(text)
    except (ValueError, argparse.ArgumentTypeError):
        return None


def _valid(bound: Bound, value) -> bool:
    if value is None:
        return False
    values = value if isinstance(value, list) else [value]
    return all(bound.holds(v) for v in values)


def _fuzz_cases() -> list[tuple[str, str, str]]:
    cases = []
    for command, action in _numeric_actions():
        flag = action.option_strings[0]
        bound = BOUNDS[command][flag]
        for text in HOSTILE:
            if not _valid(bound, _parsed(action, text)):
                cases.append((command, flag, text))
    return cases


@pytest.fixture(scope="module", autouse=True)
def one_parser():
    """``main`` parses with one parser built for the module, not a new one per call.

    Building the parser (every command, ~160 arguments) is most of a refused value's time: ~14 ms, for
    700 calls. argparse keeps nothing between parses (each gets a new namespace, defaults included), so each
    call parses as a new process's parser does.
    """
    import pasibot_pin.__main__ as entry

    parser = entry.build_parser()
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(entry, "build_parser", lambda: parser)
        yield parser


def run_cli(argv: list[str], capsys) -> tuple[int, str]:
    """``main(argv)``'s exit code (argparse's own exit too) and its stderr."""
    try:
        code = main(argv)
    except SystemExit as err:  # argparse refused the value
        code = err.code
    return code, capsys.readouterr().err


def assert_one_line_error(code: int, err: str, command: str, fragment: str) -> None:
    assert code == 2, err
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"pasibot {command}: error: "), err
    assert re.search(fragment, lines[0]), err


def _files(root: Path) -> set[Path]:
    return set(root.rglob("*"))


def test_the_floor_bound_is_the_studys():
    from pasibot_pin.studies.design_metrics import MAX_FLOOR_STEPS

    assert BOUNDS["sweep"]["--floor"].high == BOUNDS["optimize"]["--floor"].high == MAX_FLOOR_STEPS


def test_the_search_bounds_are_the_searchs_and_the_judges():
    """find-walker's budget is the search's own limit, its fewest steps the verdict's stride, its workers and seed
    the exploration's (the CLI keeps its literals to start fast: this test holds them to their sources)."""
    from pasibot_pin.dynamics.verdict import MIN_STRIDE_STEPS
    from pasibot_pin.explore.find_walker import MAX_BUDGET

    search = BOUNDS["find-walker"]
    assert search["--budget"].high == MAX_BUDGET and search["--steps"].low == MIN_STRIDE_STEPS
    assert search["--workers"] == BOUNDS["sweep"]["--workers"] and search["--seed"] == BOUNDS["sweep"]["--seed"]


def test_every_numeric_flag_has_a_bound():
    flags = {(command, action.option_strings[0]) for command, action in _numeric_actions()}
    bounded = {(command, flag) for command, table in BOUNDS.items() for flag in table}
    assert flags - bounded == set(), "numeric flags without a bound in cli/bounds.py"
    assert bounded - flags == set(), "bounds of flags that do not exist"
    assert set(BOUNDS) == set(_subparsers())


@pytest.mark.parametrize(("command", "flag", "text"), _fuzz_cases(), ids=lambda x: x or "empty")
def test_hostile_values_are_refused_naming_the_flag_and_its_range(command, flag, text, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    values = [text, "0.4"] if flag == "--sole" else [text]  # --sole HEEL TOE
    argv = [command, flag, *values, *(a.format(tmp=tmp_path) for a in REQUIRED.get(command, []))]
    before = _files(tmp_path)
    code, err = run_cli(argv, capsys)
    bound = BOUNDS[command][flag]
    assert_one_line_error(code, err, command, re.escape(flag) + ".*" + re.escape(bound.text()))
    assert _files(tmp_path) == before


# --------------------------------------------------------------------------- the fuzz's findings
_REST = SPECS["spring_rest_angle"]
REST_DEG = f"[{math.degrees(_REST.low):g}, {math.degrees(_REST.high):g}]"
"""The design record's rest angles beta0 [rad], in degrees as the flag takes them."""

CASES: list[tuple[str, str]] = [
    # hangs
    ("contact --mu 1e300", r"--mu must be in \[0, 10\], got 1e\+300"),
    ("simulate --no-cases --duration 1e-300", r"--duration must be in \[0.01, 600\] s"),
    ("simulate --no-cases --duration 0.3 --mu 1e300", r"--mu must be in \[0, 10\]"),
    ("simulate --no-cases --duration 0.3 --dt 1e-300", r"--dt must be in \[1e-05, 0.1\] s"),
    ("simulate --ground weld --no-cases --dt 1e-300", r"--dt must be in \[1e-05, 0.1\] s"),
    ("simulate --no-cases --duration 600 --dt 1e-5", r"--duration 600 s at --dt 1e-05 s gives 6e\+07 integration"),
    ("simulate --no-cases --dt 0.05", r"--dt must be in \[1e-05, 0.01\] s with --ground floor"),
    ("sweep --n 2 --workers 1 --floor 1e-300 --out {tmp}/run", r"--floor must be an integer in \[1, 1000\] steps"),
    ("sweep --n 2 --workers 1 --floor 0 --out {tmp}/run", r"--floor must be an integer in \[1, 1000\] steps, got 0"),
    ("walk --omega 1e300", r"--omega must be in \[0.05, 20\] rad/s"),
    ("walk --mu nan", r"--mu must be in \[0, 10\], got nan"),
    ("energy --nodes 1000000000", r"--nodes must be an integer in \[2, 1000\]"),
    ("energy --nodes 1000 --omegas 1,2,3,4,5,6,7,8,9,10,11", r"= 22000 inverse-dynamics nodes; at most 20000"),
    ("view --steps 1000 --samples-per-step 1000", r"--steps 1000 x --samples-per-step 1000 = 1000000 frames; at"),
    ("export-html --steps 100 --samples-per-step 101", r"= 10100 frames; at most 10000"),
    ("simulate --ground weld --no-cases --steps 1000000000", r"--steps must be an integer in \[1, 1000\]"),
    # late
    ("contact --samples 1000000000", r"--samples must be an integer in \[2, 100000\]"),
    # tracebacks
    ("view --fps 1e-300", r"--fps must be in \[0.1, 240\] 1/s"),
    ("view --hold 1e300", r"--hold must be in \[0, 86400\] s or -1 \(until Ctrl-C\)"),
    # silent accepts
    ("energy --body-mass 1e300", r"--body-mass must be in \[0.5, 500\] kg"),
    ("export-html --fps 1e-300", r"--fps must be in \[0.1, 240\]"),
    ("simulate --ground weld --rest-angle 1e300", re.escape(f"--rest-angle must be in {REST_DEG} deg")),
    ("energy --variants ,,", r"--variants must be a comma-separated list of spring, parallel"),
    ("energy --variants rigid", r"--variants: unknown variant 'rigid'; valid: spring, parallel"),
    ("contact --variant rigid", r"argument --variant: invalid choice: 'rigid'"),
    ("gait --csv {tmp}/newdir/", r"argument --csv: .*newdir/ ends in /, so it names a folder"),
    ("gait --plot {tmp}/newdir/", r"argument --plot: .*newdir/ ends in /"),
    ("export-html --out {tmp}/newdir/", r"argument --out: .*newdir/ ends in /"),
    ("sweep --method grid --n 2 --out {tmp}/run", r"--n 2 with --method grid over 7 .*take --n 128 \(2 levels\)"),
    ("sweep --method grid --n 300 --out {tmp}/run", r"take --n 128 \(2 levels\) or --n 2187 \(3 levels\)"),
    ("sweep --workers 4096 --out {tmp}/run", r"--workers must be an integer in \[1, 64\]"),
    # misleading
    ("torques --omega 1e300", r"--omega must be in \[0, 20\] rad/s"),
    ("energy --omegas 1e300", r"--omegas must be in \(0, 20\] rad/s"),
    ("energy --com-dx 1e300", r"--com-dx must be in \[-1, 1\] m"),
    ("energy --com-dx nan", r"--com-dx must be in \[-1, 1\] m, got nan"),
    ("view --reactions 1e300", r"--reactions must be in \[0, 20\] rad/s"),
    ("export-html --reactions 1e300", r"--reactions must be in \[0, 20\] rad/s"),
    ("sweep --seed -1 --out {tmp}/run", r"--seed must be an integer in \[0, 4294967295\], got -1"),
    ("optimize --seed -1 --out {tmp}/run", r"--seed must be an integer in \[0, 4294967295\], got -1"),
    ("contact --sole -2e-1 4e300", r"--sole must be in \[-2, 2\] m"),
    ("energy --com-dx -5e300", r"--com-dx must be in \[-1, 1\] m"),
    ("simulate --ground weld --gif --fps 1e300 --out {tmp}/out", r"--fps must be in \[0.1, 240\]"),
    ("simulate --ground weld --gif --fps 1e-300 --out {tmp}/out", r"--fps must be in \[0.1, 240\]"),
    ("contact --samples 1e9", r"argument --samples: invalid int value: '1e9'; --samples must be an integer in \[2"),
]


@pytest.mark.parametrize(("argv", "fragment"), CASES, ids=[c[0] for c in CASES])
def test_fuzz_findings_are_one_line_before_any_work(argv, fragment, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    args = [a.format(tmp=tmp_path) for a in argv.split()]
    before = _files(tmp_path)
    code, err = run_cli(args, capsys)
    assert_one_line_error(code, err, args[0], fragment)
    assert _files(tmp_path) == before


@pytest.mark.parametrize(
    ("argv", "dest", "value"),
    [
        (["contact", "--sole", "-2e-1", "4e-1"], "sole", [-0.2, 0.4]),
        (["energy", "--com-dx", "-5e-2"], "com_dx", -0.05),
        (["energy", "--com-dx", "-5E-2"], "com_dx", -0.05),
        (["simulate", "--rest-angle", "-1.5e1"], "rest_angle", -15.0),
        (["view", "--hold", "-1"], "hold", -1.0),
        (["torques", "--omega", "-.5"], "omega", -0.5),
    ],
)
def test_negative_numbers_in_scientific_notation_are_values(argv, dest, value):
    assert getattr(build_parser().parse_args(argv), dest) == value


# --------------------------------------------------------------------------- design files
DESIGN_COMMANDS = ["info", "gait", "torques", "contact", "energy", "build-urdf", "view", "export-html"]

BAD_DESIGNS: list[tuple[str, str, str]] = [
    ("a.toml", "ratios = 5\n", r"parameter 'ratios' must be a table of link ratios .*got 5$"),
    ("b.toml", 'ratios = "abc"\n', r"parameter 'ratios' must be a table .*got 'abc'"),
    ("c.toml", "K = " + "9" * 401 + "\n", r"parameter 'K' = a 401-digit integer \[-\] is outside \[1, 4\]"),
    ("d.toml", "K = " + "9" * 5001 + "\n", r"holds a number too long to read"),
    ("e.json", '{"ratios": [1, 2]}', r"parameter 'ratios' must be a table .*got \[1, 2\]"),
    ("f.json", "[" * 100_000 + "]" * 100_000, r"nests tables or lists too deeply"),
    ("g.toml", "a = " + "[" * 100_000 + "]" * 100_000 + "\n", r"nests tables or lists too deeply"),
    ("h.toml", 'K = "2.0"\n', r"parameter 'K' must be a number \[-\], got '2.0'"),
    ("i.toml", "K = true\n", r"parameter 'K' must be a number \[-\], got True"),
    ("j.toml", "[ratios]\nr4 = [1]\n", r"parameter 'r4' must be a number \[L\], got \[1\]"),
]


@pytest.mark.parametrize("command", DESIGN_COMMANDS)
@pytest.mark.parametrize(("name", "text", "fragment"), BAD_DESIGNS, ids=[b[0] for b in BAD_DESIGNS])
def test_bad_design_files_are_one_line(command, name, text, fragment, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / name).write_text(text)
    before = _files(tmp_path)
    code, err = run_cli([command, "--design", str(tmp_path / name)], capsys)
    assert_one_line_error(code, err, command, fragment)
    assert _files(tmp_path) == before


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"K": "2.0"}, r"parameter 'K' must be a positive finite number, got '2.0'"),
        ({"L": "2.0"}, r"parameter 'L' must be a positive finite number, got '2.0'"),
        ({"L": True}, r"parameter 'L' must be a positive finite number, got True"),
        ({"legs": True}, r"parameter 'legs' must be the integer 1 or 2, got True"),
        ({"legs": 1.0}, r"parameter 'legs' must be the integer 1 or 2, got 1.0"),
        ({"K": 10**401}, r"parameter 'K' must be a positive finite number, got a 402-digit integer"),
        ({"r4": None}, r"parameter 'r4' must be a positive finite number, got None"),
    ],
)
def test_load_refuses_wrong_types(kwargs, fragment):
    import pasibot_pin as pp
    from pasibot_pin.errors import ParameterError

    with pytest.raises(ParameterError, match=fragment):
        pp.load(**kwargs)


def test_geometry_stores_floats():
    from pasibot_pin.model.params import Geometry

    geometry = Geometry(L=1, K=2)
    assert type(geometry.L) is float and type(geometry.K) is float


# --------------------------------------------------------------------------- data safety
def test_force_keeps_a_symbolic_link_and_its_file(tmp_path, capsys):
    real = tmp_path / "real.csv"
    real.write_text("precious")
    link = tmp_path / "link.csv"
    link.symlink_to(real)
    code, err = run_cli(["gait", "--step-deg", "30", "--csv", str(link), "--force"], capsys)
    assert_one_line_error(code, err, "gait", r"--csv .*link.csv is a symbolic link \(to .*real.csv\)")
    assert link.is_symlink() and real.read_text() == "precious"


def test_force_never_replaces_a_pipe_or_a_device(tmp_path, capsys):
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    code, err = run_cli(["gait", "--step-deg", "30", "--csv", str(fifo), "--force"], capsys)
    assert_one_line_error(code, err, "gait", r"is not a regular file .*replaces only regular files")
    assert fifo.is_fifo()
    code, err = run_cli(["gait", "--step-deg", "30", "--csv", "/dev/null", "--force"], capsys)
    assert_one_line_error(code, err, "gait", r"/dev/null is not a regular file")
    assert Path("/dev/null").is_char_device()


def test_force_replaces_a_regular_file(tmp_path, capsys):
    path = tmp_path / "a.csv"
    path.write_text("old")
    assert main(["gait", "--step-deg", "30", "--csv", str(path), "--force"]) == 0
    assert path.read_text().startswith("theta")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.csv"]


def test_an_unwritable_folder_names_the_file_asked_for(tmp_path, capsys, monkeypatch):
    import errno

    def refuse(path, *args, **kwargs):
        raise PermissionError(errno.EACCES, "Permission denied", os.fspath(path))

    from pasibot_pin.cli import common

    monkeypatch.setattr(common.os, "open", refuse)
    code, err = run_cli(["gait", "--csv", str(tmp_path / "x.csv")], capsys)
    assert_one_line_error(code, err, "gait", r"--csv .*x.csv: cannot write in folder .*\(Permission denied\)")


def test_os_errors_name_the_target_not_the_temporary_file(tmp_path):
    from pasibot_pin.files import atomic_path

    target = tmp_path / "a.csv"
    with pytest.raises(PermissionError) as info, atomic_path(target) as tmp:
        raise PermissionError(13, "Permission denied", str(tmp))
    assert info.value.filename == str(target)
    assert list(tmp_path.iterdir()) == []


def test_an_overwrite_refusal_names_out_when_out_named_the_file(tmp_path, capsys):
    (tmp_path / "gait_spring_1leg.csv").write_text("mine")
    code, err = run_cli(["gait", "--legs", "1", "--step-deg", "30", "--out", str(tmp_path)], capsys)
    assert_one_line_error(code, err, "gait", r"^pasibot gait: error: --out .*gait_spring_1leg.csv exists")


def test_a_second_run_on_a_locked_folder_is_refused(tmp_path, capsys):
    from pasibot_pin.files import OutputFolder

    out = tmp_path / "run"
    holder = OutputFolder(out).claim()  # another run writing there
    try:
        code, err = run_cli(["sweep", "--n", "2", "--workers", "1", "--out", str(out), "--no-progress"], capsys)
        assert_one_line_error(code, err, "sweep", rf"--out {re.escape(str(out))} is in use by another pasibot run")
        code, err = run_cli(["analyze", "--out", str(out)], capsys)
        assert_one_line_error(code, err, "analyze", r"is in use by another pasibot run")
    finally:
        holder.release()
    assert sorted(p.name for p in out.iterdir()) == [".pasibot"]


def test_force_is_refused_in_a_folder_pasibot_did_not_make(tmp_path, capsys):
    out = tmp_path / "mine"
    (out / "best").mkdir(parents=True)
    (out / "best" / "thesis.tex").write_text("precious")
    (out / "notes.txt").write_text("mine")  # not a name pasibot writes: the folder is not pasibot's
    code, err = run_cli(["sweep", "--n", "2", "--workers", "1", "--out", str(out), "--force"], capsys)
    assert_one_line_error(code, err, "sweep", r"holds files pasibot did not write .*use another folder")
    assert (out / "best" / "thesis.tex").read_text() == "precious"
    code, err = run_cli(["analyze", "--out", str(out), "--force"], capsys)
    assert_one_line_error(code, err, "analyze", r"holds files pasibot did not write")
    assert sorted(p.name for p in out.iterdir()) == ["best", "notes.txt"]


def test_a_run_folder_of_an_older_pasibot_counts_as_pasibots(tmp_path):
    from pasibot_pin.explore.store import OWNED
    from pasibot_pin.files import MARKER, OutputFolder

    (tmp_path / "plan.json").write_text("{}")
    (tmp_path / "parts").mkdir()
    folder = OutputFolder(tmp_path, ours=OWNED).claim(force=True)
    assert (tmp_path / MARKER).is_file()
    folder.release()


def test_a_failed_run_removes_what_it_created(tmp_path, capsys, monkeypatch):
    """optimize failing inside the run (after plan.json, optuna.log, parts/) leaves no folder behind."""
    from pasibot_pin.explore import optimize

    def failing(plan, folder, **kwargs):
        (Path(folder) / "parts").mkdir(parents=True, exist_ok=True)
        (Path(folder) / "plan.json").write_text("{}")
        (Path(folder) / "optuna.log").write_text("")
        raise ValueError("parameter 'x' broke")

    monkeypatch.setattr(optimize, "run_optimize", failing)
    out = tmp_path / "new" / "run"
    code, err = run_cli(["optimize", "--trials", "2", "--workers", "1", "--out", str(out), "--no-progress"], capsys)
    assert_one_line_error(code, err, "optimize", "parameter 'x' broke")
    assert list(tmp_path.iterdir()) == []  # new/ too: this run made it
    existing = tmp_path / "empty"
    existing.mkdir()
    code, err = run_cli(["optimize", "--trials", "2", "--workers", "1", "--out", str(existing)], capsys)
    assert code == 2
    assert existing.is_dir() and list(existing.iterdir()) == []  # the folder stays, emptied of this run's files


def test_workers_are_capped_to_the_tasks(monkeypatch):
    from pasibot_pin import jobs
    from pasibot_pin.explore.executors import run_tasks

    seen = {}

    def fake_run_jobs(job_list, on_done, workers, **kwargs):
        seen["workers"] = workers
        for job in job_list:
            on_done(job.key, job.fn(*job.args))

    monkeypatch.setattr(jobs, "run_jobs", fake_run_jobs)
    results = []
    run_tasks(abs, [(-1,), (-2,), (-3,)], results.append, workers=32)
    assert seen["workers"] == 3 and sorted(results) == [1, 2, 3]


def test_a_figure_is_never_left_half_written(tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from pasibot_pin.viz import figure_files

    def half(fig, path, dpi):
        Path(path).write_bytes(b"\x89PNG half")
        raise KeyboardInterrupt

    monkeypatch.setattr(figure_files, "_save_figure", half)
    fig = plt.figure()
    with pytest.raises(KeyboardInterrupt):
        figure_files.save_figure_file(fig, tmp_path / "walk.png")
    plt.close(fig)
    assert list(tmp_path.iterdir()) == []


def test_a_signal_removes_the_temporary_files_being_written(tmp_path):
    from pasibot_pin.files import LIVE_TEMPORARIES, atomic_path, remove_temporaries

    with pytest.raises(KeyboardInterrupt), atomic_path(tmp_path / "a.csv") as tmp:
        tmp.write_text("half")
        assert os.fspath(tmp) in LIVE_TEMPORARIES
        remove_temporaries()  # what the SIGTERM/SIGINT handler does, in the main process and in workers
        assert not tmp.exists()
        raise KeyboardInterrupt
    assert list(tmp_path.iterdir()) == []
    assert not LIVE_TEMPORARIES
