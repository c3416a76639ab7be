"""A quick look at a network address before a client library waits on it.

Dask's client retries a scheduler address until its timeout, and a ZMQ request waits for a reply
that never comes; a closed port, though, refuses a plain TCP connection at once.
"""

from __future__ import annotations

import socket
from urllib.parse import urlsplit

PROBE_TIMEOUT = 1.0
"""How long the plain TCP connection may take [s] before the address is left to the client library."""


def tcp_refused(address: str) -> str:
    """Why a ``tcp://host:port`` address refuses a plain TCP connection.

    Args:
        address: a URL such as ``tcp://127.0.0.1:8786``.

    Returns:
        A short reason (``connection refused by host:port``, or the URL's own fault such as a port
        that is not a number), or ``""`` when the port accepts a connection, does not answer within
        :data:`PROBE_TIMEOUT`, or the address is not ``tcp://host:port``: then the client library's
        own attempt decides.

    """
    try:
        parts = urlsplit(address)
        host, port = parts.hostname, parts.port
    except ValueError as err:  # a port that is not a number
        return str(err)
    if parts.scheme != "tcp" or host is None or port is None:
        return ""
    try:
        socket.create_connection((host, port), timeout=PROBE_TIMEOUT).close()
    except ConnectionRefusedError:
        return f"connection refused by {host}:{port}"
    except OSError:
        return ""
    return ""
