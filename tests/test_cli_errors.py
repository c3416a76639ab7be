"""Bad input is refused before any work: one line on stderr, exit code 2, no traceback, no file.

Each case is ``argv -> fragment of the message``. ``{locked}`` is a folder nobody may write
(mode 0o500; as root, where chmod stops nothing, a regular file standing where a folder should
be), ``{dir}`` an existing folder and ``{tmp}`` a fresh folder.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from pasibot_pin.__main__ import main

LOCKED = r"(is not writable|is a file, not a folder)"

CASES: list[tuple[str, str]] = [
    # unwritable folders (PermissionError tracebacks before)
    ("build-urdf --out {locked}/a.urdf", LOCKED),
    ("gait --csv {locked}/a.csv", LOCKED),
    ("gait --plot {locked}/a.png", LOCKED),
    ("torques --csv {locked}/a.csv", LOCKED),
    ("simulate --ground weld --out {locked}/sim --no-cases", LOCKED),
    ("simulate --out {locked}/sim --no-cases", LOCKED),
    ("export-html --out {locked}/a.html", LOCKED),
    ("analyze --out {locked}/out", LOCKED),  # checked before any work
    # a folder where a file should be (IsADirectoryError before)
    ("build-urdf --out {dir}", "is a folder"),
    ("gait --csv {dir} --force", "is a folder"),
    ("gait --plot {dir} --force", "is a folder"),
    # memory (MemoryError before)
    ("gait --step-deg 1e-9", "at most"),
    ("gait --legs 2 --steps 1000000000", r"--steps must be an integer in \[1, 1000\]"),
    ("gait --legs 2 --steps 1000 --step-deg 0.1", "at most 1000000"),
    ("torques --samples 100000000", r"--samples must be an integer in \[2, 100000\]"),
    ("torques --steps 1000 --samples 1000", "exceeds 100000"),
    # silent accepts
    ("build-urdf --K 5", r"--K must be in \[1, 4\]"),
    ("build-urdf --K 3.5", "cannot make a full turn"),
    ("build-urdf --K 1.2", "cannot make a full turn"),
    ("build-urdf --K 1e200 --L 1e200", r"--L must be in \[0.005, 2\] m"),
    ("simulate --ground weld --dt 0", r"--dt must be in \[1e-05, 0.1\] s"),
    ("simulate --ground weld --dt 1e6", r"--dt must be in \[1e-05, 0.1\] s"),
    ("simulate --ground weld --dt nan", r"--dt must be in \[1e-05, 0.1\] s, got nan"),
    ("simulate --dt 0", r"--dt must be in \[1e-05, 0.1\] s"),
    ("simulate --dt 1", r"--dt must be in \[1e-05, 0.1\] s"),
    ("simulate --mu -1", r"--mu must be in \[0, 10\]"),
    ("simulate --duration 0", r"--duration must be in \[0.01, 600\] s"),
    ("simulate --duration nan", r"--duration must be in \[0.01, 600\] s, got nan"),
    ("simulate --scenario quasi-static", "does not walk"),
    ("simulate --stiffness 300", "--ground weld"),
    ("simulate --gif", "--ground weld"),
    ("simulate --steps 3", "--ground weld"),
    ("energy --flywheel -1", r"--flywheel must be in \(0, 1000\] kg.m\^2"),
    ("energy --flywheel 0", r"--flywheel must be in \(0, 1000\]"),
    ("view --hold nan", "--hold"),
    ("torques --preset seed --samples -3", r"--samples must be an integer in \[2, 100000\]"),
    ("torques --samples -3", r"--samples must be an integer in \[2, 100000\], got -3"),
    ("torques --preset seed --steps 2", "parameter 'steps' must be 1 with preset 'seed'"),
    ("gait --legs 1 --foot point", "'--foot' applies to --legs 2"),
    ("gait --legs 2 --foot heel", "'--foot' must be one of"),
    ("build-urdf --ratio K=3", "--ratio expects rN=VALUE"),
    # fails only after the work (before)
    ("simulate --ground weld --fps 0 --gif", r"--fps must be in \[0.1, 240\] 1/s"),
    ("gait --csv {tmp}/a.csv --plot {tmp}/a.xyz", "matplotlib cannot write .xyz"),
    ("torques --csv {tmp}/a.csv --plot {tmp}/a.docx", "matplotlib cannot write .docx"),
    ("build-urdf --ratio ratios=1", "--ratio expects rN=VALUE"),
    # said in the user's words (issue 34)
    ("walk --design {dir}", "is a folder"),
    ("walk --design /dev/null", "not a regular file"),
    ("walk --steps 1 --out {tmp}/anim", "--out names the folder of --gif and --html"),
    ("contact --sole -1e-300 1e-300", "--sole must be"),
    ("contact --sole 0 0.4", "--sole must be"),
    ("sweep --vary sole_inner=0.6:1 --n 2 --3d --out {tmp}/s", "give --floor"),
    # the work bounded before it starts (issue 34)
    ("walk --steps 1000 --omega 0.05", r"--steps 1000 at --omega 0.05 rad/s: .* past the limit.*a faster crank$"),
    ("walk --steps 300 --omega 0.5 --3d", "past the limit"),
    (
        "sweep --vary omega=0.05:0.1 --n 2000 --floor 100 --out {tmp}/s",
        r"--floor 100 for 2000 designs: .* past the limit.* or fewer designs$",
    ),
]


@pytest.fixture
def locked(tmp_path):
    """A folder no one may write into (root: a file where the folder should be)."""
    if os.geteuid() == 0:  # chmod does not stop root: a path through a regular file fails for root too
        path = tmp_path / "locked"
        path.write_text("a file, not a folder\n")
        yield path
        return
    path = tmp_path / "locked"
    path.mkdir()
    path.chmod(0o500)
    yield path
    path.chmod(0o700)


def _files(root: Path) -> set[Path]:
    return {p for p in root.rglob("*")}


def run_cli(argv: list[str], capsys) -> tuple[int, str]:
    code = main(argv)
    err = capsys.readouterr().err
    return code, err


def assert_one_line_error(code: int, err: str, command: str, fragment: str) -> None:
    import re

    assert code == 2, err
    assert "Traceback" not in err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith(f"pasibot {command}: error: "), err
    assert re.search(fragment, lines[0]), err


@pytest.mark.parametrize(("argv", "fragment"), CASES, ids=[c[0] for c in CASES])
def test_bad_input_is_one_line_exit_2_and_writes_nothing(argv, fragment, tmp_path, locked, capsys, monkeypatch):
    folder = tmp_path / "existing"
    folder.mkdir()
    work = tmp_path / "cwd"
    work.mkdir()
    monkeypatch.chdir(work)  # default outputs (out/, gait.html) land here, and must not appear
    args = argv.format(locked=locked, dir=folder, tmp=tmp_path).split()
    before = _files(tmp_path)
    code, err = run_cli(args, capsys)
    assert_one_line_error(code, err, args[0], fragment)
    assert _files(tmp_path) == before  # nothing written, no half file


def test_zmq_url_without_server_is_refused_within_seconds(capsys):
    import time

    start = time.monotonic()
    code, err = run_cli(["view", "--zmq-url", "tcp://127.0.0.1:1"], capsys)
    assert_one_line_error(code, err, "view", "no meshcat server answered at tcp://127.0.0.1:1")
    assert time.monotonic() - start < 30


def test_plot_without_extension_checks_the_png_that_would_be_written(tmp_path, capsys):
    (tmp_path / "walk.png").write_text("precious")
    code, err = run_cli(["gait", "--plot", str(tmp_path / "walk")], capsys)
    assert_one_line_error(code, err, "gait", r"walk\.png exists; pass --force")
    assert (tmp_path / "walk.png").read_text() == "precious"


def test_plot_without_extension_writes_png(tmp_path, capsys):
    assert main(["gait", "--step-deg", "30", "--plot", str(tmp_path / "walk")]) == 0
    assert "wrote " + str(tmp_path / "walk.png") in capsys.readouterr().out
    assert sorted(p.name for p in tmp_path.iterdir()) == ["walk.png"]  # no temporary file left


def test_build_urdf_defaults_refuses_site_packages(tmp_path, capsys, monkeypatch):
    from pasibot_pin.model import description

    installed = tmp_path / "lib" / "python3" / "site-packages" / "pasibot_pin" / "urdf"
    installed.mkdir(parents=True)
    monkeypatch.setattr(description, "URDF_DIR", installed)
    code, err = run_cli(["build-urdf", "--defaults"], capsys)
    assert_one_line_error(code, err, "build-urdf", "installed package .*--out FOLDER")
    assert list(installed.iterdir()) == []


def test_build_urdf_defaults_into_a_folder(tmp_path, capsys):
    assert main(["build-urdf", "--defaults", "--out", str(tmp_path / "urdf")]) == 0
    names = sorted(p.name for p in (tmp_path / "urdf").iterdir())
    assert names == sorted(f"pasibot_{v}_{n}leg.urdf" for v in ("rigid", "parallel", "spring") for n in (1, 2))


def test_os_errors_during_work_are_one_line(tmp_path, capsys, monkeypatch):
    """A write the system refuses after the checks (a full disk, a race) is still one line, exit 2."""
    from pasibot_pin.report import files

    def refuse(*args, **kwargs):
        raise PermissionError(13, "Permission denied", str(tmp_path / "a.csv"))

    monkeypatch.setattr(files.csv, "writer", refuse)
    code, err = run_cli(["gait", "--step-deg", "30", "--csv", str(tmp_path / "a.csv")], capsys)
    assert_one_line_error(code, err, "gait", "a.csv: Permission denied")
    assert list(tmp_path.iterdir()) == []  # the temporary file is gone too


def test_analyze_refuses_a_folder_with_files_before_any_work(tmp_path, capsys):
    from pasibot_pin.__main__ import main

    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")
    assert main(["analyze", "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "already holds files" in err and "--force" in err and "\n" not in err
    assert [p.name for p in out.iterdir()] == ["notes.txt"]


def test_one_writer_per_folder_for_walk_and_stale_parts_are_cleared(tmp_path, capsys):
    """walk --gif locks its --out: a second writer is refused at once; a half file a killed run left
    (.NAME.part-*) is removed by the next run that holds the folder (issue 34)."""
    from pasibot_pin.files import OutputFolder

    out = tmp_path / "anim"
    holder = OutputFolder(out).claim()
    try:
        code, err = run_cli(["walk", "--steps", "3", "--gif", "--out", str(out)], capsys)
        assert_one_line_error(code, err, "walk", "in use by another pasibot run")
    finally:
        holder.release()
    stale = out / ".walk_seed.part-0123abcd.gif"
    stale.write_bytes(b"half a gif")
    again = OutputFolder(out).claim()
    again.release()
    assert not stale.exists()


def test_a_failed_run_removes_only_what_it_made(tmp_path):
    """A run that created runs/ and runs/a, then failed, removes runs/a, and runs/ only if nothing else
    moved in: another run's runs/b stays (issue 34)."""
    from pasibot_pin.files import OutputFolder

    mine = OutputFolder(tmp_path / "runs" / "a").claim()
    other = tmp_path / "runs" / "b"
    other.mkdir()
    (other / "results.parquet").write_bytes(b"another sweep's table")
    mine.discard()
    assert not (tmp_path / "runs" / "a").exists() and (other / "results.parquet").is_file()
    alone = OutputFolder(tmp_path / "new" / "deep" / "c").claim()
    alone.discard()
    assert not (tmp_path / "new").exists()  # everything it made, when nothing else moved in


@pytest.mark.integration
def test_a_reader_that_leaves_early_ends_the_command_quietly(tmp_path):
    """`pasibot walk ... | head -1`: a broken pipe is not an error (exit 0, nothing on stderr; issue 34)."""
    import subprocess
    import sys

    proc = subprocess.Popen(
        [sys.executable, "-m", "pasibot_pin", "walk", "--variant", "parallel", "--omega", "3", "--steps", "3"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=tmp_path,
    )  # fmt: skip
    assert proc.stdout is not None
    proc.stdout.close()  # the reader leaves before the walk prints, as `| true` does (or head -1 after a line)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 0 and b"Broken pipe" not in err and b"Traceback" not in err, err
