"""Reading back a static meshcat page (``WalkViewer.static_html``): its embedded commands, shared by the page tests."""

from __future__ import annotations

import base64
import re

import umsgpack


def decode_commands(html: str) -> list[dict]:
    """Every meshcat command embedded in a static_html() page."""
    blobs = re.findall(r"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)", html)
    return [umsgpack.unpackb(base64.b64decode(b)) for b in blobs]
