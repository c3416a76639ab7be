"""The meshcat server of the live viewer: a child process bound to 127.0.0.1, gone with its parent.

meshcat's own ``meshcat-server`` binds its web port on every interface (0.0.0.0);
:func:`start_server` runs the same ZMQ/web bridge (:func:`serve_loopback`) in a child process
with the web server bound to the loopback address. The child asks the kernel for a SIGTERM when
its parent dies, even on SIGKILL (Linux), and the parent stops it at exit.
:func:`check_meshcat_server` asks a server someone else started for its address, with a timeout.
"""

from __future__ import annotations

import atexit
import ctypes
import ctypes.util
import functools
import os
import signal
import subprocess
import sys
import time
from dataclasses import dataclass

from pasibot_pin.errors import ParameterError
from pasibot_pin.net import tcp_refused

__all__ = ["LOOPBACK", "ZMQ_TIMEOUT", "ServerProcess", "check_meshcat_server", "serve_loopback", "start_server"]

LOOPBACK = "127.0.0.1"
"""The only address the viewer's own server listens on."""

ZMQ_TIMEOUT = 2.0
"""How long :func:`check_meshcat_server` waits for a reused meshcat server to answer [s]."""


@dataclass
class ServerProcess:
    """A meshcat ZMQ/web bridge running in a child process, bound to 127.0.0.1.

    Attributes:
        process: the child process.
        zmq_url: where clients send commands (``tcp://127.0.0.1:PORT``).
        web_url: the page to open in a browser (``http://127.0.0.1:PORT/static/``).

    """

    process: subprocess.Popen
    zmq_url: str
    web_url: str

    @property
    def web_port(self) -> int:
        """TCP port of the web server."""
        return int(self.web_url.split(":")[2].split("/")[0])

    @property
    def zmq_port(self) -> int:
        """TCP port of the ZMQ command socket."""
        return int(self.zmq_url.rsplit(":", 1)[1])

    def close(self) -> None:
        """Stop the server (idempotent)."""
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=5)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait()
        for stream in (self.process.stdout, self.process.stderr):
            if stream is not None:
                stream.close()


def serve_loopback() -> None:
    """Run meshcat's ZMQ/web bridge with both sockets on 127.0.0.1 (child-process entry point)."""
    from meshcat.servers.zmqserver import ZMQWebSocketBridge  # deferred: heavy (meshcat), keeps the CLI's start fast

    class LoopbackBridge(ZMQWebSocketBridge):
        def make_app(self):  # noqa: D102 - meshcat API
            app = super().make_app()
            any_address_listen = app.listen

            def listen(port, address=None, **kwargs):
                return any_address_listen(port, address=LOOPBACK, **kwargs)

            app.listen = listen
            return app

    bridge = LoopbackBridge(host=LOOPBACK)
    print(f"zmq_url={bridge.zmq_url}", flush=True)
    print(f"web_url={bridge.web_url}", flush=True)
    bridge.run()


def _die_with_parent(parent: int) -> None:
    """In the server child, before ``exec``: the kernel sends SIGTERM when the parent dies, even on SIGKILL.

    Linux's ``prctl(PR_SET_PDEATHSIG)``; elsewhere a no-op (the parent's ``atexit`` still stops the
    server on a normal exit). ``parent`` is the parent's pid: had it died before the call, exit at once.
    """
    if not sys.platform.startswith("linux"):
        return
    pr_set_pdeathsig = 1
    libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6", use_errno=True)
    libc.prctl(pr_set_pdeathsig, int(signal.SIGTERM), 0, 0, 0)
    if os.getppid() != parent:
        os._exit(1)


def start_server(timeout: float = 30.0) -> ServerProcess:
    """Start a meshcat server whose ZMQ and web sockets listen on 127.0.0.1 only.

    Args:
        timeout: how long to wait for the server to report its addresses [s].

    Returns:
        The running :class:`ServerProcess` (stopped at interpreter exit, or by ``close()``).

    Raises:
        RuntimeError: the server did not start.

    """
    if not timeout > 0:
        raise ParameterError(f"parameter 'timeout' must be > 0 s, got {timeout!r}")

    code = "from pasibot_pin.viz.meshcat_server import serve_loopback; serve_loopback()"
    process = subprocess.Popen(
        [sys.executable, "-u", "-c", code],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
        text=True,
        preexec_fn=functools.partial(_die_with_parent, os.getpid()),  # gone with us, even on SIGKILL
    )
    server = ServerProcess(process, "", "")
    atexit.register(server.close)  # at once: a Ctrl-C from here on still stops the server
    urls: dict[str, str] = {}
    try:
        deadline = time.monotonic() + timeout
        while len(urls) < 2:
            line = process.stdout.readline() if process.stdout is not None else ""  # piped: never None
            if not line:
                process.wait(timeout=5)
                raise RuntimeError(f"the meshcat server exited with code {process.returncode} before it was ready")
            key, _, value = line.strip().partition("=")
            if key in ("zmq_url", "web_url"):
                urls[key] = value
            if time.monotonic() > deadline:
                raise RuntimeError(f"the meshcat server did not start within {timeout} s")
    except BaseException:
        server.close()
        atexit.unregister(server.close)
        raise
    server.zmq_url, server.web_url = urls["zmq_url"], urls["web_url"]
    return server


def check_meshcat_server(zmq_url: str, timeout: float = ZMQ_TIMEOUT) -> str:
    """Ask the meshcat server at ``zmq_url`` for its web address, waiting at most ``timeout`` [s].

    meshcat's own client waits forever for a server that does not answer; this asks first (and a
    closed port is refused at once, without the wait).

    Returns:
        The server's web address.

    Raises:
        ValueError: nothing answered at ``zmq_url`` within ``timeout``.

    """
    import zmq  # deferred: heavy (zmq), keeps the CLI's start fast

    refused = tcp_refused(zmq_url)
    if refused:
        raise ParameterError(
            f"parameter 'zmq_url': no meshcat server answered at {zmq_url} ({refused}; start one with "
            "meshcat-server, or leave --zmq-url out to start our own)"
        )
    context: zmq.Context = zmq.Context.instance()
    socket = context.socket(zmq.REQ)
    socket.setsockopt(zmq.LINGER, 0)
    try:
        socket.connect(zmq_url)
        socket.send(b"url")
        if not socket.poll(int(timeout * 1000), zmq.POLLIN):
            raise ParameterError(
                f"parameter 'zmq_url': no meshcat server answered at {zmq_url} within {timeout:g} s "
                "(start one with meshcat-server, or leave --zmq-url out to start our own)"
            )
        return socket.recv().decode()
    except zmq.ZMQError as err:
        raise ParameterError(f"parameter 'zmq_url': cannot reach {zmq_url}: {err}") from None
    finally:
        socket.close(linger=0)
