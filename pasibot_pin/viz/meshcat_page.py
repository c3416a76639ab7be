"""The exported meshcat page: its commands reordered, a title bar and the ``#t=`` seek script.

meshcat's static page replays the scene tree's commands in tree order; the animation sits on the
root node, so it would come first and the nodes' static poses after it: :func:`animation_last`
moves it to the end (the commands are base64 msgpack blobs, read by :func:`command_type`). The
page gets a title bar (:class:`Hud`: meshcat has no text overlay of its own) with the scene's
title, the time, the crank angle and each foot's contact mode, following the animation, and
:data:`SEEK_SCRIPT`, inside meshcat's own script before its commands: ``#t=SECONDS`` in the address
pauses the animation at that time (a still for screenshots and bookmarks); without it the walk
plays in a loop. :func:`finish_page` does all three.
"""

from __future__ import annotations

import base64
import html as html_text
import json
import math
import re
from dataclasses import dataclass

import numpy as np

__all__ = ["HUD_SCRIPT", "SEEK_SCRIPT", "Hud", "animation_last", "command_type", "finish_page"]

HUD_SCRIPT = """
<div id="pasibot-hud" style="position:fixed;top:8px;left:8px;z-index:10;padding:4px 8px;font:14px sans-serif;
background:rgba(255,255,255,0.85);border-radius:4px;pointer-events:none;white-space:pre"></div>
<script>
// pasibot_pin: the title, time, crank angle and foot modes of the frame the animation shows.
(function () {
  var info = HUD_INFO;
  var hud = document.getElementById("pasibot-hud");
  function text(k) {
    var modes = Object.keys(info.modes).map(function (s) { return s + ": " + info.modes[s][k]; }).join("   ");
    return info.title + "\\nt = " + info.t[k].toFixed(2) + " s   crank angle = " + info.theta[k].toFixed(1) +
      " deg   " + modes;
  }
  function tick() {
    var a = viewer.animator, time = 0;
    if (a && a.actions && a.actions.length) { time = a.actions[0].time; }
    var k = Math.max(0, Math.min(info.t.length - 1, Math.round(time * info.fps)));
    hud.textContent = text(k);
    window.requestAnimationFrame(tick);
  }
  hud.textContent = text(0);
  window.requestAnimationFrame(tick);
})();
</script>
"""

SEEK_SCRIPT = """
// pasibot_pin: '#t=SECONDS' in the address pauses the walk at that time; without it the walk loops.
(function () {
  var match = /[#&]t=([0-9.eE+-]+)/.exec(window.location.hash);
  if (!match) { return; }
  var seconds = parseFloat(match[1]);
  var handle = viewer.handle_command.bind(viewer);
  var animation = null;
  function seek() {
    viewer.animator.pause();
    viewer.animator.seek(seconds);
    document.title = "pasibot t=" + seconds;
  }
  viewer.handle_command = function (command) {
    if (command.type === "set_animation") {
      animation = JSON.stringify(command);
      handle(command);
      seek();
      return;
    }
    handle(command);
    if (animation !== null) {
      // A static pose arrived after the animation: three.js writes a keyframe value only when it
      // changes, so rebuild the animation (a fresh mixer) and seek again.
      handle(JSON.parse(animation));
      seek();
    }
  };
})();
"""
"""The seek's JavaScript. :func:`finish_page` puts it into meshcat's own script, right after the viewer is made
and before the first command is fetched: the commands arrive by ``fetch()``, whose callbacks may run as soon as
the parser yields, so a script placed after them could wrap ``handle_command`` only once the animation had
arrived (seen once, in a fresh clone's test run: a page asked for ``#t=0.5`` played instead)."""

VIEWER_MADE = 'var viewer = new MeshCat.Viewer(document.getElementById("meshcat-pane"));'
"""The statement of meshcat's static page that makes the viewer; the commands' fetches follow it."""


_COMMAND = re.compile(
    r'fetch\("data:application/octet-binary;base64,(?P<data>[A-Za-z0-9+/=]+)"\)\s*'
    r"\.then\(res => res\.arrayBuffer\(\)\)\s*"
    r"\.then\(buffer => viewer\.handle_command_bytearray\(new Uint8Array\(buffer\)\)\);"
)


def command_type(packed: bytes) -> str:
    """The ``type`` of a msgpack-packed meshcat command.

    Every command's ``lower()`` puts ``type`` first, so it is read from the first bytes (a map
    header, the key ``type``, a short string); anything else is unpacked whole.
    """
    if len(packed) > 6 and packed[1:6] == b"\xa4type" and 0xA0 <= packed[6] <= 0xBF:
        return packed[7 : 7 + (packed[6] & 0x1F)].decode("utf-8")
    import umsgpack  # deferred: heavy (umsgpack), keeps the CLI's start fast

    return umsgpack.unpackb(packed)["type"]


def animation_last(html: str) -> str:
    """Move the ``set_animation`` command(s) of a meshcat static page after every other command."""
    commands = list(_COMMAND.finditer(html))
    if not commands:
        raise RuntimeError("no meshcat commands found in static_html()")
    moved = [m for m in commands if command_type(base64.b64decode(m["data"])) == "set_animation"]
    if not moved:
        return html
    end = commands[-1].end()
    kept = html[:end]
    for m in reversed(moved):
        kept = kept[: m.start()] + kept[m.end() :]
    return kept + "\n" + "\n".join(m.group(0) for m in moved) + html[end:]


@dataclass
class Hud:
    """The exported page's title bar: one entry per animation frame.

    Attributes:
        title: what is shown (scenario, variant).
        fps: animation frames per second [1/s].
        t: time of each frame [s] (the walk's or the simulation's).
        theta: right crank angle of each frame [rad].
        modes: side -> contact mode of each frame.

    """

    title: str
    fps: float
    t: np.ndarray
    theta: np.ndarray
    modes: dict[str, list[str]]

    def script(self) -> str:
        """The HUD's HTML and script, its data embedded as JSON (angles in degrees)."""
        info = {
            "title": self.title,
            "fps": self.fps,
            "t": [round(float(x), 6) for x in self.t],
            "theta": [round(math.degrees(float(x)), 4) for x in self.theta],
            "modes": {side: list(m) for side, m in self.modes.items()},
        }
        return HUD_SCRIPT.replace("HUD_INFO", json.dumps(info).replace("</", "<\\/"))  # no "</script>" inside


def finish_page(page: str, hud: Hud | None) -> str:
    """The static page of meshcat with its animation last, the title bar (``hud``, if any) and the seek script."""
    page = animation_last(page)
    if hud is not None:  # before the insertion point is found: the title changes the length
        page = page.replace("<title>MeshCat</title>", f"<title>{html_text.escape(hud.title)}</title>", 1)
    made = page.find(VIEWER_MADE)
    if made < 0:
        raise RuntimeError("meshcat's static_html() makes no viewer where expected")
    made += len(VIEWER_MADE)
    page = page[:made] + SEEK_SCRIPT + page[made:]  # before the first command is fetched (SEEK_SCRIPT)
    at = page.rfind("</body>")
    if at < 0:
        raise RuntimeError("meshcat's static_html() has no </body>")
    return page[:at] + (hud.script() if hud is not None else "") + page[at:]
