"""The quick TCP look before a client library waits (``pasibot_pin.net``) and the waits it spares."""

from __future__ import annotations

import socket
import time

import pytest

from pasibot_pin.net import tcp_refused

pytestmark = [pytest.mark.network]


@pytest.fixture()
def silent_port():
    """A port that accepts TCP connections and never says a word."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen()
    try:
        yield server.getsockname()[1]
    finally:
        server.close()


def _closed_port() -> int:
    probe = socket.socket()
    probe.bind(("127.0.0.1", 0))
    port = probe.getsockname()[1]
    probe.close()  # bound, never listened: nothing accepts there now
    return port


def test_a_closed_port_is_refused_at_once():
    port = _closed_port()
    start = time.monotonic()
    assert tcp_refused(f"tcp://127.0.0.1:{port}") == f"connection refused by 127.0.0.1:{port}"
    assert time.monotonic() - start < 0.5


def test_an_open_port_and_other_addresses_are_left_to_the_client(silent_port):
    assert tcp_refused(f"tcp://127.0.0.1:{silent_port}") == ""
    assert tcp_refused("tls://127.0.0.1:1") == ""  # not plain tcp: the library decides
    assert tcp_refused("tcp://127.0.0.1") == ""  # no port
    assert "integer" in tcp_refused("tcp://127.0.0.1:abc")


def test_a_silent_meshcat_port_still_times_out(silent_port):
    """Open but not a meshcat server: the ZMQ request's own timeout answers (here 0.3 s)."""
    from pasibot_pin.viz.viewer import check_meshcat_server

    start = time.monotonic()
    with pytest.raises(ValueError, match="no meshcat server answered .* within 0.3 s"):
        check_meshcat_server(f"tcp://127.0.0.1:{silent_port}", timeout=0.3)
    assert time.monotonic() - start < 5


def test_a_closed_dask_port_is_refused_before_dasks_own_timeout():
    import distributed  # noqa: F401 (imported before the clock starts: its import alone took 1.2 s on a loaded machine)

    from pasibot_pin.explore.executors import check_scheduler

    port = _closed_port()
    start = time.monotonic()
    reason = f"cannot reach a Dask scheduler there \\(connection refused by 127.0.0.1:{port}"
    with pytest.raises(ValueError, match=reason):
        check_scheduler(f"tcp://127.0.0.1:{port}")
    assert time.monotonic() - start < 1.0
