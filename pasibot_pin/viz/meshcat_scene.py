"""A meshcat scene kept in this process, for self-contained HTML pages without a server.

meshcat's ``Visualizer`` sends every command over ZMQ to a server process, which keeps the
scene tree and, asked for ``get_scene``, renders the tree into one HTML page. Writing a page
needs no browser and no socket, so :class:`OfflineWindow` stands in for meshcat's
``ViewerWindow``: each command goes straight to meshcat's own server code
(``ZMQWebSocketBridge.handle_zmq``) running on a tree held here, with no process, socket or
web server. The page is the one a fresh server would return: the same page around the same
commands in the same order (``tests/test_viewer.py`` builds one scene both ways and compares;
meshcat names objects by time-based uuids, so no two builds are byte-identical).

This leans on meshcat's server internals (its ``tree`` attribute and ``handle_zmq``), which
the pinned range ``meshcat>=0.3.2,<0.4`` keeps.
"""

from __future__ import annotations


class _Replies:
    """Stands in for the server's ZMQ socket: keeps the last reply."""

    def __init__(self) -> None:
        self.last = b""

    def send(self, data: bytes) -> None:
        """Keep ``data`` (the server's reply to the last command)."""
        self.last = data


class OfflineWindow:
    """A meshcat window whose scene lives in this process (``meshcat.Visualizer(window=...)``).

    Attributes:
        web_url: empty: there is no live page to open.

    """

    web_url = ""

    def __init__(self) -> None:
        from meshcat.servers.tree import SceneTree  # deferred: heavy (meshcat), keeps the CLI's start fast
        from meshcat.servers.zmqserver import (  # deferred: heavy (meshcat), keeps the CLI's start fast
            ZMQWebSocketBridge,
        )

        self._handle = ZMQWebSocketBridge.handle_zmq
        bridge = object.__new__(ZMQWebSocketBridge)  # the state handle_zmq uses, without sockets
        bridge.tree = SceneTree()
        bridge.zmq_socket = _Replies()
        bridge.forward_to_websockets = lambda frames: None  # no browser is connected
        self._bridge = bridge

    def _request(self, frames: list[bytes]) -> bytes:
        self._handle(self._bridge, frames)
        reply = self._bridge.zmq_socket.last
        if reply.startswith(b"error"):
            raise RuntimeError(f"meshcat scene: {reply.decode()}")
        return reply

    def send(self, command) -> None:
        """Apply one meshcat command (``SetObject``, ``SetTransform``, ...) to the scene."""
        import umsgpack  # deferred: heavy (umsgpack), keeps the CLI's start fast

        data = command.lower()
        self._request([data["type"].encode("utf-8"), data["path"].encode("utf-8"), umsgpack.packb(data)])

    def get_scene(self) -> str:
        """The whole scene as one self-contained HTML page (meshcat's ``static_html``)."""
        return self._request([b"get_scene"]).decode("utf-8")

    def open(self):
        """There is no page to open: an offline scene is only written out."""
        raise RuntimeError("an offline meshcat scene has no live page; write it with static_html()")

    def close(self) -> None:
        """Nothing to stop."""
