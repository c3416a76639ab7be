"""SIGTERM and Ctrl-C stop a command and every process it started, within seconds, leaving no half file."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

import pytest

from pasibot_pin.__main__ import descendants

pytestmark = [pytest.mark.integration, pytest.mark.slow]

SETTLE = 0.3
"""Seconds between the children starting and the signal: they are then at work (importing,
computing), which is when a stop must still clean up."""


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as handle:
            stat = handle.read()
    except OSError:
        return False
    return not stat[stat.rfind(")") + 2 :].startswith("Z")


def _wait_for(predicate, timeout: float) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.1)
    return False


def _start(args: list[str], cwd) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "pasibot_pin", *args],
        cwd=cwd,
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,  # its own process group, as a terminal's foreground job
    )


def _stop_and_check(proc: subprocess.Popen, sig: int, children: list[int], group: bool, ok=()) -> str:
    start = time.monotonic()
    if group:  # Ctrl-C in a terminal: the whole foreground group gets SIGINT
        os.killpg(proc.pid, sig)
    else:
        proc.send_signal(sig)
    try:
        _, err = proc.communicate(timeout=20)
    except subprocess.TimeoutExpired:
        proc.kill()
        for pid in children:
            if _alive(pid):
                os.kill(pid, signal.SIGKILL)
        pytest.fail("the command did not exit within 20 s of the signal")
    elapsed = time.monotonic() - start
    left = [pid for pid in children if _alive(pid)]
    for pid in left:
        os.kill(pid, signal.SIGKILL)
    assert not left, f"orphan processes {left}"
    assert proc.returncode in (128 + sig, *ok), err
    assert "Traceback" not in err
    assert elapsed < 15, f"took {elapsed:.1f} s to exit"
    return err


@pytest.mark.parametrize(("sig", "group"), [(signal.SIGTERM, False), (signal.SIGINT, True)])
def test_view_stops_its_meshcat_server(tmp_path, sig, group):
    proc = _start(["view", "--steps", "1", "--samples-per-step", "4", "--hold", "-1"], tmp_path)
    try:
        assert _wait_for(lambda: len(descendants(proc.pid)) >= 1, 120), "the meshcat server never started"
        assert proc.poll() is None
    except BaseException:
        proc.kill()
        raise
    time.sleep(SETTLE)
    children = descendants(proc.pid)
    # Ctrl-C is the documented end of --hold -1: exit code 0 then
    err = _stop_and_check(proc, sig, children, group, ok=(0,) if sig == signal.SIGINT else ())
    assert sig == signal.SIGINT or "terminated" in err


@pytest.mark.parametrize(("sig", "group"), [(signal.SIGTERM, False), (signal.SIGINT, True)])
def test_analyze_stops_its_pool_workers_and_leaves_no_half_file(tmp_path, sig, group):
    out = tmp_path / "out"
    proc = _start(["analyze", "--out", str(out)], tmp_path)
    try:
        # the pool's workers (pasibot_pin.jobs.WORKERS) are running
        from pasibot_pin.jobs import WORKERS

        assert _wait_for(lambda: len(descendants(proc.pid)) >= WORKERS, 180), "the pool never started"
    except BaseException:
        proc.kill()
        raise
    time.sleep(SETTLE)
    children = descendants(proc.pid)
    assert len(children) >= 2
    _stop_and_check(proc, sig, children, group)
    assert not [p for p in out.rglob("*") if ".part-" in p.name]  # no temporary file left
    assert not out.exists()  # a stopped run leaves nothing it created (no half figure under its name either)


def test_ctrl_c_while_the_server_starts_stops_it(monkeypatch):
    """A Ctrl-C that lands before the server reported its address still stops the server."""
    from pasibot_pin.viz import meshcat_server

    started: list[subprocess.Popen] = []
    real_popen = subprocess.Popen

    class Recording(real_popen):
        def __init__(self, *args, **kwargs):
            super().__init__(*args, **kwargs)
            started.append(self)

    def interrupt():
        raise KeyboardInterrupt

    monkeypatch.setattr(meshcat_server.subprocess, "Popen", Recording)
    monkeypatch.setattr(meshcat_server.time, "monotonic", interrupt)
    with pytest.raises(KeyboardInterrupt):
        meshcat_server.start_server()
    assert len(started) == 1
    assert started[0].poll() is not None  # stopped, not left to the end of the interpreter


@pytest.mark.parametrize(("sig", "group"), [(signal.SIGINT, True), (signal.SIGTERM, False)])
def test_sweep_stops_its_workers_and_keeps_its_rows(tmp_path, sig, group, capsys):
    """Ctrl-C or SIGTERM in a sweep: no orphan worker, no half file, the finished designs kept, a rerun continues."""
    import pyarrow.parquet as pq

    from pasibot_pin.__main__ import main

    out = tmp_path / "run"
    args = ["sweep", "--n", "400", "--vary", "K=1.8:2.4", "--workers", "2", "--out", str(out), "--no-progress"]
    proc = _start(args, tmp_path)
    parts = out / "parts"
    assert _wait_for(lambda: parts.is_dir() and any(parts.glob("part-*.parquet")), 120), "no design finished"
    children = descendants(proc.pid)
    _stop_and_check(proc, sig, children, group)
    assert not list(out.rglob("*.tmp")) and not [p for p in out.rglob("*") if ".part-" in p.name]
    kept = sum(pq.read_table(p).num_rows for p in parts.glob("part-*.parquet"))
    assert 0 < kept < 400
    capsys.readouterr()
    again = main([*args[:2], "12", *args[3:]])  # in this process: refused before any work, no pool started
    assert again == 2 and "different run" in capsys.readouterr().err  # another --n is another run


def test_ctrl_c_while_the_command_still_imports_is_one_line_and_130():
    """Found by a fuzz at random moments: a Ctrl-C during ``pasibot``'s imports (its first second, before
    ``main`` installs its handlers) printed a KeyboardInterrupt traceback. The package, imported by our
    command line, exits 130 with one line; imported as a library it leaves Ctrl-C as Python's."""
    as_command = (
        "import os, signal, sys, time; sys.argv = ['pasibot']; import pasibot_pin; "
        "os.kill(os.getpid(), signal.SIGINT); time.sleep(5); print('not stopped')"
    )
    done = subprocess.run([sys.executable, "-c", as_command], capture_output=True, text=True, timeout=60)
    assert done.returncode == 130 and done.stderr == "pasibot: interrupted\n" and "not stopped" not in done.stdout
    # as it found it: Python's own handler, or SIG_IGN where the caller ignores Ctrl-C (a job started in the background)
    as_library = "import signal; before = signal.getsignal(signal.SIGINT); import pasibot_pin; "
    as_library += "print(signal.getsignal(signal.SIGINT) is before)"
    done = subprocess.run([sys.executable, "-c", as_library], capture_output=True, text=True, timeout=60)
    assert done.stdout.strip() == "True", done.stderr
