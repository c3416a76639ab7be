"""``pasibot view``'s meshcat server dies with the command, even when the command is SIGKILLed.

SIGKILL runs no handler and no ``atexit``: only the kernel can stop the child, through the
parent-death signal the child asks for before it runs (``prctl(PR_SET_PDEATHSIG)``).
"""

from __future__ import annotations

import os
import re
import signal
import socket
import subprocess
import sys
import time

import pytest

from pasibot_pin.__main__ import descendants

pytestmark = [
    pytest.mark.skipif(not sys.platform.startswith("linux"), reason="PR_SET_PDEATHSIG is Linux's"),
    pytest.mark.network,
]


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as handle:
            stat = handle.read()
    except OSError:
        return False
    return not stat[stat.rfind(")") + 2 :].startswith("Z")


def _listening(port: int) -> bool:
    with socket.socket() as s:
        s.settimeout(1.0)
        return s.connect_ex(("127.0.0.1", port)) == 0


def _wait_for(predicate, timeout: float) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.1)
    return predicate()


def test_view_server_dies_with_a_sigkilled_command(tmp_path):
    proc = subprocess.Popen(
        [sys.executable, "-m", "pasibot_pin", "view", "--steps", "1", "--samples-per-step", "3", "--hold", "-1"],
        cwd=tmp_path,
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    children: list[int] = []
    try:
        url = None
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline:
            line = proc.stdout.readline()
            if not line:
                break
            found = re.search(r"viewer: http://127\.0\.0\.1:(\d+)/", line)
            url = url or (found and int(found.group(1)))
            if "serving until Ctrl-C" in line:
                break
        assert url, "the view command printed no viewer address"
        port = url
        children = descendants(proc.pid)
        assert children, "the meshcat server child is not running"
        assert _listening(port)
        proc.send_signal(signal.SIGKILL)
        proc.wait(timeout=10)
        assert _wait_for(lambda: not any(_alive(pid) for pid in children), 5.0), "the server outlived its parent"
        assert _wait_for(lambda: not _listening(port), 5.0), f"port {port} still listening"
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
        for pid in children:
            if _alive(pid):
                os.kill(pid, signal.SIGKILL)
