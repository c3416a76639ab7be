"""Browser 3-D viewer: the walking biped in meshcat, live or as one self-contained HTML file.

:class:`WalkViewer` wraps Pinocchio's ``MeshcatVisualizer``. It draws the robot's visuals
coloured by group (the colours of :data:`pasibot_pin.viz.plots.GROUP_COLOURS`), a ground slab
whose top is the plane z = 0, the foot paths of a walk as lines, and optional force arrows.
The hip body is drawn transparent (:data:`HIP_OPACITY`) so the far leg's linkage shows through it;
every joint is marked by a small sphere, and the sole points touching the ground by green ones
(:mod:`pasibot_pin.viz.contacts`). It plays a walk live (:meth:`WalkViewer.play`) or stores it as
a meshcat ``Animation`` (:meth:`WalkViewer.set_walk_animation`), which :meth:`WalkViewer.static_html` embeds into one
HTML file that plays offline (:func:`export_html`).

The server listens on 127.0.0.1 only. meshcat's own ``meshcat-server`` binds its web port
on every interface (0.0.0.0); :func:`start_server` runs the same bridge with the web
server bound to the loopback address. Pass ``zmq_url=`` to reuse a ``meshcat-server`` you
started yourself (its binding is then yours).

The exported page carries a title bar (a HUD: meshcat has no text overlay of its own) with the
scene's title, the time, the crank angle and each foot's contact mode, following the animation.
It understands ``#t=SECONDS`` in its address: it pauses the animation at that
time (a still for screenshots and bookmarks). Without it the walk plays in a loop.

Lengths [m], forces [N], time [s].
"""

from __future__ import annotations

import atexit
import base64
import contextlib
import io
import math
import re
import subprocess
import sys
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import pinocchio as pin

from pasibot_pin.viz.plots import GROUP_COLOURS, link_group

LOOPBACK = "127.0.0.1"
"""The only address the viewer's own server listens on."""

ROOT = "pasibot"
"""Root node of the robot in the meshcat scene."""

PATH_COLOURS: dict[str, str] = {"right": "#d62728", "left": "#8e44ad", "hip": "#555555"}
"""Colours of the foot-path (ankle) and hip traces."""

GROUND_COLOUR = "#cfc8b8"
FORCE_COLOUR = "#e6007e"
CUT_FORCE_COLOUR = "#ffd400"

JOINT_COLOUR = "#222222"
CONTACT_COLOUR = "#1a9e3a"
HIP_OPACITY = 0.25
"""Opacity of the hip body: it would hide the far leg's linkage."""
JOINT_RADIUS = 0.012
"""Radius of the joint markers [m]."""
CONTACT_RADIUS = 0.02
"""Radius of the contact-point markers [m]."""

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

GROUND_THICKNESS = 0.01
"""Thickness of the ground slab [m]."""

ZMQ_TIMEOUT = 2.0
"""How long :func:`check_meshcat_server` waits for a reused meshcat server to answer [s]."""

LOOP_REPETITIONS = 1_000_000
"""Repetitions of the exported animation (it loops for as long as anyone watches)."""

SEEK_SCRIPT = """
<script>
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
</script>
"""


_COMMAND = re.compile(
    r'fetch\("data:application/octet-binary;base64,(?P<data>[A-Za-z0-9+/=]+)"\)\s*'
    r"\.then\(res => res\.arrayBuffer\(\)\)\s*"
    r"\.then\(buffer => viewer\.handle_command_bytearray\(new Uint8Array\(buffer\)\)\);"
)


def _command_type(packed: bytes) -> str:
    """The ``type`` of a msgpack-packed meshcat command.

    Every command's ``lower()`` puts ``type`` first, so it is read from the first bytes (a map
    header, the key ``type``, a short string); anything else is unpacked whole.
    """
    if len(packed) > 6 and packed[1:6] == b"\xa4type" and 0xA0 <= packed[6] <= 0xBF:
        return packed[7 : 7 + (packed[6] & 0x1F)].decode("utf-8")
    import umsgpack

    return umsgpack.unpackb(packed)["type"]


def _animation_last(html: str) -> str:
    """Move the ``set_animation`` command(s) of a meshcat static page after every other command."""
    commands = list(_COMMAND.finditer(html))
    if not commands:
        raise RuntimeError("no meshcat commands found in static_html()")
    moved = [m for m in commands if _command_type(base64.b64decode(m["data"])) == "set_animation"]
    if not moved:
        return html
    end = commands[-1].end()
    kept = html[:end]
    for m in reversed(moved):
        kept = kept[: m.start()] + kept[m.end() :]
    return kept + "\n" + "\n".join(m.group(0) for m in moved) + html[end:]


def _rgba(colour: str) -> np.ndarray:
    """'#rrggbb' -> RGBA floats in [0, 1]."""
    value = colour.lstrip("#")
    return np.array([int(value[i : i + 2], 16) / 255.0 for i in (0, 2, 4)] + [1.0])


def _hex_int(colour: str) -> int:
    """'#rrggbb' -> 0xrrggbb."""
    return int(colour.lstrip("#"), 16)


# --------------------------------------------------------------------------- server


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


def _serve_loopback() -> None:
    """Run meshcat's ZMQ/web bridge with both sockets on 127.0.0.1 (child-process entry point)."""
    from meshcat.servers.zmqserver import ZMQWebSocketBridge

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
    import ctypes
    import ctypes.util
    import os
    import signal

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
        raise ValueError(f"parameter 'timeout' must be > 0 s, got {timeout!r}")
    import functools
    import os

    code = "from pasibot_pin.viz.viewer import _serve_loopback; _serve_loopback()"
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
            line = process.stdout.readline()
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
    import zmq

    from pasibot_pin.net import tcp_refused

    refused = tcp_refused(zmq_url)
    if refused:
        raise ValueError(
            f"parameter 'zmq_url': no meshcat server answered at {zmq_url} ({refused}; start one with "
            "meshcat-server, or leave --zmq-url out to start our own)"
        )
    context = zmq.Context.instance()
    socket = context.socket(zmq.REQ)
    socket.setsockopt(zmq.LINGER, 0)
    try:
        socket.connect(zmq_url)
        socket.send(b"url")
        if not socket.poll(int(timeout * 1000), zmq.POLLIN):
            raise ValueError(
                f"parameter 'zmq_url': no meshcat server answered at {zmq_url} within {timeout:g} s "
                "(start one with meshcat-server, or leave --zmq-url out to start our own)"
            )
        return socket.recv().decode()
    except zmq.ZMQError as err:
        raise ValueError(f"parameter 'zmq_url': cannot reach {zmq_url}: {err}") from None
    finally:
        socket.close(linger=0)


# --------------------------------------------------------------------------- scene content


def coloured_visual_model(robot) -> pin.GeometryModel:
    """A copy of the robot's visual model with every object coloured by its link's group.

    The group (hoeken, pantograph, extension, foot, hip) comes from
    :func:`pasibot_pin.viz.plots.link_group`, the colours from :data:`GROUP_COLOURS`, so the
    3-D view and the 2-D plots agree.
    """
    visual = robot.visual_model.copy()
    for obj in visual.geometryObjects:
        group = link_group(robot.model.frames[obj.parentFrame].name)
        obj.meshColor = _rgba(GROUP_COLOURS[group])
        if group == "hip":  # see-through: the far leg's linkage shows behind it
            obj.meshColor[3] = HIP_OPACITY
    return visual


def marker_tracks(robot, qs: np.ndarray, modes: Mapping[str, Sequence[str]] | None = None) -> dict:
    """Positions of the joint and contact markers along a trajectory.

    Args:
        robot: the robot.
        qs: configurations (N, nq).
        modes: each foot's contact mode per frame (default: from the geometry,
            :func:`pasibot_pin.viz.contacts.foot_contacts`).

    Returns:
        ``{node: (positions (N, 3) [m], shown (N,) bool)}``: ``joints/<joint>`` for every joint and
        cut joint, ``contacts/<side>_<heel|toe>`` shown where that point touches the ground.

    """
    from pasibot_pin.viz.contacts import foot_contacts

    qs = _check_trajectory(robot, qs)
    model, data = robot.model, robot.model.createData()
    joints = {model.names[j]: j for j in range(1, model.njoints)}
    cuts = {f.name: robot.frame_id(f.name) for f in model.frames if "_loop_" in f.name and f.name.endswith("_a")}
    out = {f"joints/{name}": np.zeros((len(qs), 3)) for name in [*joints, *cuts]}
    for k, q in enumerate(qs):
        pin.framesForwardKinematics(model, data, q)
        for name, j in joints.items():
            out[f"joints/{name}"][k] = data.oMi[j].translation
        for name, fid in cuts.items():
            out[f"joints/{name}"][k] = data.oMf[fid].translation
    tracks = {node: (pos, np.ones(len(qs), bool)) for node, pos in out.items()}
    contacts = foot_contacts(robot, qs)
    for side, points in contacts.points.items():
        for i, point in enumerate(("heel", "toe")):
            shown = contacts.touching[side][:, i]
            if modes is not None:
                shown = np.array([m not in ("air",) for m in modes[side]]) & shown
            tracks[f"contacts/{side}_{point}"] = (points[:, i].copy(), shown)
    return tracks


def _mark_transform(position: np.ndarray, shown: bool) -> np.ndarray:
    T = np.eye(4)
    T[:3, 3] = position
    if not shown:  # hidden: shrunk to nothing (meshcat animates transforms, not visibility)
        T[:3, :3] *= 1e-6
    return T


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
        import json

        info = {
            "title": self.title,
            "fps": self.fps,
            "t": [round(float(x), 6) for x in self.t],
            "theta": [round(math.degrees(float(x)), 4) for x in self.theta],
            "modes": {side: list(m) for side, m in self.modes.items()},
        }
        return HUD_SCRIPT.replace("HUD_INFO", json.dumps(info).replace("</", "<\\/"))  # no "</script>" inside


def sole_depth(robot) -> float:
    """How far the foot visuals reach below their sole plane (the foot frame's z = 0) [m]."""
    depth = 0.0
    for obj in robot.visual_model.geometryObjects:
        if not robot.model.frames[obj.parentFrame].name.endswith("_foot"):
            continue
        half = getattr(obj.geometry, "halfSide", None)
        if half is None:
            continue
        corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)]) * half
        in_foot = robot.model.frames[obj.parentFrame].placement.inverse() * obj.placement  # placement: joint frame
        z = (corners @ in_foot.rotation.T + in_foot.translation)[:, 2]
        depth = max(depth, -float(z.min()))
    return depth


def frame_paths(robot, qs: np.ndarray, frames: Sequence[str]) -> dict[str, np.ndarray]:
    """World positions of ``frames`` over a trajectory: ``{frame: (N, 3)}`` [m]."""
    qs = _check_trajectory(robot, qs)
    ids = {name: robot.frame_id(name) for name in frames}
    out = {name: np.zeros((len(qs), 3)) for name in frames}
    data = robot.model.createData()
    for k, q in enumerate(qs):
        pin.framesForwardKinematics(robot.model, data, q)
        for name, fid in ids.items():
            out[name][k] = data.oMf[fid].translation
    return out


def foot_paths(robot, qs: np.ndarray) -> dict[str, np.ndarray]:
    """Ankle paths of every leg over a trajectory: ``{'right': (N, 3), 'left': (N, 3)}`` [m]."""
    sides = [s for s in ("right", "left") if robot.model.existFrame(f"{s}_foot")]
    paths = frame_paths(robot, qs, [f"{s}_foot" for s in sides])
    return {s: paths[f"{s}_foot"] for s in sides}


def _check_trajectory(robot, qs) -> np.ndarray:
    qs = np.atleast_2d(np.asarray(qs, dtype=float))
    if qs.ndim != 2 or qs.shape[1] != robot.model.nq or len(qs) == 0:
        raise ValueError(f"parameter 'qs' must have shape (N, {robot.model.nq}), got {np.shape(qs)}")
    if not np.all(np.isfinite(qs)):
        raise ValueError("parameter 'qs' contains non-finite values")
    return qs


def _check_fps(fps: float) -> float:
    if not (isinstance(fps, (int, float)) and math.isfinite(fps) and fps > 0):
        raise ValueError(f"parameter 'fps' must be a positive frame rate [1/s], got {fps!r}")
    return float(fps)


def _arrow_transform(point: np.ndarray, force: np.ndarray, scale: float) -> tuple[np.ndarray, float]:
    """Pose (4x4, unit scale) that points the arrow's local x along ``force``, and its length [m]."""
    length = float(np.linalg.norm(force)) * scale
    T = np.eye(4)
    T[:3, 3] = point
    if length > 0.0:
        x = force / np.linalg.norm(force)
        helper = np.array([0.0, 0.0, 1.0]) if abs(x[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
        y = np.cross(helper, x)
        y /= np.linalg.norm(y)
        T[:3, :3] = np.column_stack([x, y, np.cross(x, y)])
    return T, length


@dataclass
class ForceTrack:
    """A force to draw as an arrow at each frame of a trajectory.

    Attributes:
        points: application points (N, 3) [m], world frame.
        forces: force vectors (N, 3) [N], world frame.
        scale: arrow length per newton [m/N].
        colour: '#rrggbb'.

    """

    points: np.ndarray
    forces: np.ndarray
    scale: float
    colour: str = FORCE_COLOUR

    def __post_init__(self) -> None:
        self.points = np.asarray(self.points, dtype=float)
        self.forces = np.asarray(self.forces, dtype=float)
        if self.points.ndim != 2 or self.points.shape[1] != 3 or self.forces.shape != self.points.shape:
            raise ValueError("ForceTrack: parameters 'points' and 'forces' must both have shape (N, 3)")
        if not (np.all(np.isfinite(self.points)) and np.all(np.isfinite(self.forces))):
            raise ValueError("ForceTrack: parameters 'points' and 'forces' must be finite")
        if not (math.isfinite(self.scale) and self.scale > 0):
            raise ValueError(f"ForceTrack: parameter 'scale' must be a positive [m/N], got {self.scale}")


def quasi_static_ground_reaction(robot, qs: np.ndarray, stance: Sequence[str], scale: float = 5e-4) -> ForceTrack:
    """The ground's total force on the robot when it walks slowly (omega -> 0), per frame.

    With negligible accelerations the only external forces are gravity and the ground, so the
    ground pushes up with the whole weight, along the vertical through the centre of mass
    (the centre of pressure lies below the COM). The arrow starts on the ground (z = 0) below
    the COM, in the stance leg's plane.

    Args:
        robot: a two-legged robot.
        qs: configurations (N, nq).
        stance: the stance side at each frame (``'right'`` / ``'left'``), e.g. ``walk.stance``.
        scale: arrow length per newton [m/N].

    Returns:
        A :class:`ForceTrack` with forces (0, 0, m g) [N].

    """
    qs = _check_trajectory(robot, qs)
    if len(stance) != len(qs) or any(s not in ("right", "left") for s in stance):
        raise ValueError("parameter 'stance' must give 'right' or 'left' for every frame")
    data = robot.model.createData()
    mass = sum(inertia.mass for inertia in robot.model.inertias)
    weight = mass * float(np.linalg.norm(robot.model.gravity.linear))
    points = np.zeros((len(qs), 3))
    for k, q in enumerate(qs):
        com = pin.centerOfMass(robot.model, data, q)
        pin.framesForwardKinematics(robot.model, data, q)
        points[k] = [com[0], data.oMf[robot.frame_id(f"{stance[k]}_foot")].translation[1], 0.0]
    forces = np.tile([0.0, 0.0, weight], (len(qs), 1))
    return ForceTrack(points, forces, scale)


def reaction_forces(
    robot, walk, omega: float = 0.0, ground_scale: float = 5e-4, cut_scale: float | None = None
) -> dict[str, ForceTrack]:
    """Ground reaction and cut-joint forces along a walk, from :func:`pasibot_pin.dynamics.inverse_dynamics`.

    The ground's in-plane wrench on the stance foot (Fx, Fz and the moment about the ankle)
    is drawn as one force through the centre of pressure, on the ground. Each cut joint's
    force on the first link of its pair is drawn at the joint.

    Args:
        robot: the two-legged ``spring`` robot.
        walk: a :class:`pasibot_pin.kinematics.gait.Walk` of that robot (flat feet).
        omega: crank speed [rad/s]; 0 = quasi-static.
        ground_scale: arrow length per newton of the ground reaction [m/N].
        cut_scale: arrow length per newton of the cut forces [m/N]; default: the largest
            cut force is drawn 0.15 m long.

    Returns:
        ``{'ground': ..., 'stance_j2': ..., 'swing_j5': ...}`` :class:`ForceTrack` objects.

    """
    from pasibot_pin.dynamics import inverse as dynamics

    res = dynamics.inverse_dynamics(robot, walk.theta, omega)
    data = robot.model.createData()
    n = len(walk.q)
    ground_points, ground_forces = np.zeros((n, 3)), np.zeros((n, 3))
    cut_points = {name: np.zeros((n, 3)) for name in res.cuts}
    for k, q in enumerate(walk.q):
        pin.framesForwardKinematics(robot.model, data, q)
        side = res.stance[k]
        fx, fz, moment = res.ground[k]
        if not abs(fz) > 1e-9:
            raise ValueError(f"no vertical ground reaction at frame {k}: the centre of pressure is undefined")
        ankle = data.oMf[robot.frame_id(f"{side}_foot")].translation
        ground_points[k] = [ankle[0] + moment / fz, ankle[1], 0.0]
        ground_forces[k] = [fx, 0.0, fz]
        for name in res.cuts:
            role, joint = name.split("_", 1)
            leg = side if role == "stance" else ("left" if side == "right" else "right")
            cut_points[name][k] = data.oMf[robot.frame_id(f"{leg}_loop_{joint}_a")].translation
    tracks = {"ground": ForceTrack(ground_points, ground_forces, ground_scale)}
    largest = max(float(np.linalg.norm(f, axis=1).max()) for f in res.cuts.values()) if res.cuts else 0.0
    if cut_scale is None:
        cut_scale = 0.15 / largest if largest > 0 else 1.0
    for name, f in res.cuts.items():
        forces = np.column_stack([f[:, 0], np.zeros(n), f[:, 1]])
        tracks[name] = ForceTrack(cut_points[name], forces, cut_scale, colour=CUT_FORCE_COLOUR)
    return tracks


# --------------------------------------------------------------------------- viewer


@dataclass
class WalkViewer:
    """The robot in a meshcat scene, with ground, foot paths, force arrows and animation.

    Args:
        robot: a loaded robot (:func:`pasibot_pin.load`).
        zmq_url: reuse a running ``meshcat-server`` at this address; ``None`` starts a
            server of our own bound to 127.0.0.1 (:func:`start_server`).
        open: open the page in the default web browser.
        offline: keep the scene in this process, with no server and no live page
            (:class:`~pasibot_pin.viz.meshcat_scene.OfflineWindow`): for writing
            :meth:`static_html` only (what :func:`export_html` does).

    """

    robot: object
    zmq_url: str | None = None
    open: bool = False
    offline: bool = False
    server: ServerProcess | None = field(init=False, default=None)

    def __post_init__(self) -> None:
        import meshcat
        from pinocchio.visualize import MeshcatVisualizer

        if self.offline:
            from pasibot_pin.viz.meshcat_scene import OfflineWindow

            if self.zmq_url is not None or self.open:
                raise ValueError("an offline viewer has no server: pass neither 'zmq_url' nor open=True")
            self.meshcat = meshcat.Visualizer(window=OfflineWindow())
        elif self.zmq_url is None:
            self.server = start_server()
            self.zmq_url = self.server.zmq_url
        elif not isinstance(self.zmq_url, str) or not self.zmq_url.startswith(("tcp://", "ipc://")):
            raise ValueError(f"parameter 'zmq_url' must look like tcp://HOST:PORT, got {self.zmq_url!r}")
        else:
            check_meshcat_server(self.zmq_url)
        if not self.offline:
            with contextlib.redirect_stdout(io.StringIO()):  # meshcat prints its URL; ``url`` has it
                self.meshcat = meshcat.Visualizer(zmq_url=self.zmq_url)
        self.visual_model = coloured_visual_model(self.robot)
        self.viz = MeshcatVisualizer(
            self.robot.model, self.robot.collision_model, self.visual_model, data=self.robot.model.createData()
        )
        self.viz.initViewer(viewer=self.meshcat, open=False)
        self.viz.loadViewerModel(rootNodeName=ROOT)
        self.meshcat["/Grid"].set_property("visible", False)
        self.meshcat["/Axes"].set_property("visible", False)
        self.forces: dict[str, ForceTrack] = {}
        self.marks: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        self.hud: Hud | None = None
        self.display(self.robot.q0)
        if self.open:
            self.meshcat.open()

    # ---- basics

    @property
    def url(self) -> str:
        """Address of the viewer page."""
        return self.meshcat.url()

    def jupyter_cell(self, height: int = 500):
        """The live viewer as an inline notebook cell (an IPython HTML object)."""
        return self.meshcat.jupyter_cell(height=height)

    def display(self, q: np.ndarray) -> None:
        """Place the robot at configuration ``q``."""
        self.viz.display(_check_trajectory(self.robot, q)[0])

    def show_robot(self, visible: bool = True) -> None:
        """Show or hide the robot's visuals, joint and contact markers (the ground, paths and arrows stay)."""
        for node in ("visuals", "joints", "contacts"):
            self.meshcat[f"{ROOT}/{node}"].set_property("visible", bool(visible))

    def visual_nodes(self) -> list[str]:
        """Scene path of every visual object of the robot (under the viewer's root)."""
        return [self.viz.getViewerNodeName(obj, pin.GeometryType.VISUAL) for obj in self.visual_model.geometryObjects]

    def visual_poses(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """World pose (4x4) of every visual node at ``q``, as sent to the viewer."""
        q = _check_trajectory(self.robot, q)[0]
        data, gdata = self.viz.data, self.viz.visual_data
        pin.forwardKinematics(self.robot.model, data, q)
        pin.updateGeometryPlacements(self.robot.model, data, self.visual_model, gdata)
        out = {}
        for gid, obj in enumerate(self.visual_model.geometryObjects):
            T = gdata.oMg[gid].homogeneous.copy()
            T[:3, :3] = T[:3, :3] @ np.diag(obj.meshScale)
            out[self.viz.getViewerNodeName(obj, pin.GeometryType.VISUAL)] = T
        return out

    # ---- static scene

    def add_ground(self, x_range: tuple[float, float], width: float = 0.6, top: float | None = None) -> None:
        """A ground slab spanning ``x_range`` [m] and ``width`` across [m].

        Args:
            x_range: (start, end) of the slab along x [m].
            width: extent across (y) [m].
            top: height of its top face [m]; default :func:`sole_depth` below z = 0: the
                URDF's foot box hangs below the sole (the contact plane z = 0), so the slab
                sits under it instead of hiding the stance foot.

        """
        import meshcat.geometry as mg

        x0, x1 = float(x_range[0]), float(x_range[1])
        if not (math.isfinite(x0) and math.isfinite(x1) and x1 > x0):
            raise ValueError(f"parameter 'x_range' must be an increasing pair of finite x [m], got {x_range!r}")
        if not width > 0:
            raise ValueError(f"parameter 'width' must be > 0 m, got {width!r}")
        top = -sole_depth(self.robot) if top is None else float(top)
        node = self.meshcat[f"{ROOT}/ground"]
        material = mg.MeshLambertMaterial(color=_hex_int(GROUND_COLOUR))
        node.set_object(mg.Box([x1 - x0, width, GROUND_THICKNESS]), material)
        T = np.eye(4)
        T[:3, 3] = [(x0 + x1) / 2, 0.0, top - GROUND_THICKNESS / 2]
        node.set_transform(T)

    def add_path(self, name: str, points: np.ndarray, colour: str) -> None:
        """A polyline through ``points`` (N, 3) [m], world frame."""
        import meshcat.geometry as mg

        points = np.asarray(points, dtype=float)
        if points.ndim != 2 or points.shape[1] != 3 or len(points) < 2 or not np.all(np.isfinite(points)):
            raise ValueError(f"parameter 'points' of path {name!r} must be finite with shape (N >= 2, 3)")
        line = mg.Line(mg.PointsGeometry(points.T.astype(np.float32)), mg.LineBasicMaterial(color=_hex_int(colour)))
        self.meshcat[f"{ROOT}/paths/{name}"].set_object(line)

    def add_foot_paths(self, qs: np.ndarray) -> dict[str, np.ndarray]:
        """Draw the ankle path of each leg (and the hip path of a biped) over ``qs``; returns them [m]."""
        paths = foot_paths(self.robot, qs)
        if self.robot.floating:
            paths["hip"] = frame_paths(self.robot, qs, ["hip"])["hip"]
        for name, pts in paths.items():
            self.add_path(name, pts, PATH_COLOURS[name])
        return paths

    def add_markers(self, qs: np.ndarray, modes: Mapping[str, Sequence[str]] | None = None) -> None:
        """Joint markers (dark spheres) and contact points (green spheres) along ``qs`` (see :func:`marker_tracks`)."""
        import meshcat.geometry as mg

        self.marks = marker_tracks(self.robot, qs, modes)
        joint = mg.MeshLambertMaterial(color=_hex_int(JOINT_COLOUR))
        contact = mg.MeshLambertMaterial(color=_hex_int(CONTACT_COLOUR))
        for node, (positions, shown) in self.marks.items():
            is_joint = node.startswith("joints/")
            sphere = mg.Sphere(JOINT_RADIUS if is_joint else CONTACT_RADIUS)
            self.meshcat[f"{ROOT}/{node}"].set_object(sphere, joint if is_joint else contact)
            self.meshcat[f"{ROOT}/{node}"].set_transform(_mark_transform(positions[0], shown[0]))

    def add_force(self, name: str, track: ForceTrack) -> None:
        """An arrow (unit length along its local x, stretched per frame) for a force track."""
        import meshcat.geometry as mg

        if not isinstance(track, ForceTrack):
            raise ValueError("parameter 'track' must be a ForceTrack")
        material = mg.MeshLambertMaterial(color=_hex_int(track.colour))
        radius = 0.006
        y_to_x = np.array([[0.0, 1.0, 0.0, 0.0], [-1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 1.0, 0.0], [0.0, 0.0, 0.0, 1.0]])

        def along_x(geometry, centre):
            T = y_to_x.copy()
            T[0, 3] = centre
            # meshcat writes this matrix row by row; three.js reads it column by column.
            return type("AlongX", (type(geometry),), {"intrinsic_transform": lambda self: T.T})

        shaft = mg.Cylinder(0.8, radius)
        shaft.__class__ = along_x(shaft, 0.4)
        head = mg.Cylinder(0.2, radiusTop=0.0, radiusBottom=2.5 * radius)
        head.__class__ = along_x(head, 0.9)
        node = self.meshcat[f"{ROOT}/forces/{name}"]
        node["shaft"].set_object(shaft, material)
        node["head"].set_object(head, material)
        self.forces[name] = track
        self._place_force(node, track, 0)

    @staticmethod
    def _place_force(node, track: ForceTrack, k: int) -> None:
        T, length = _arrow_transform(track.points[k], track.forces[k], track.scale)
        T[:3, 0] *= max(length, 1e-6)
        node.set_transform(T)

    def set_side_camera(self, qs: np.ndarray, distance: float | None = None) -> None:
        """Look at the walk from the robot's right side (from -y), centred on its bounding box.

        Args:
            qs: the trajectory to frame (N, nq).
            distance: camera distance from the walk's centre [m]; default fits the walk.

        """
        qs = _check_trajectory(self.robot, qs)
        pts = []
        for q in qs[:: max(1, len(qs) // 20)]:
            pts += [T[:3, 3] for T in self.visual_poses(q).values()]
        pts = np.array(pts)
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        lo[2] = min(lo[2], 0.0)
        centre = (lo + hi) / 2
        extent = float(max(hi[0] - lo[0], hi[2] - lo[2]))
        distance = 0.8 * extent + 0.25 if distance is None else float(distance)
        if not distance > 0:
            raise ValueError(f"parameter 'distance' must be > 0 m, got {distance!r}")
        # meshcat's orbit controls always aim at the scene origin: shift the robot's root
        # node so that the walk's centre sits there (poses below the root stay world poses).
        T = np.eye(4)
        T[:3, 3] = -centre
        self.meshcat[ROOT].set_transform(T)
        # The camera's own frame is three.js's y-up frame: (x, z, -y) of ours.
        self.meshcat["/Cameras/default/rotated/<object>"].set_property("position", [0.0, 0.0, distance])

    # ---- motion

    def play(self, qs: np.ndarray, fps: float = 30.0, repetitions: int = 1) -> None:
        """Play a trajectory live, frame by frame at ``fps`` [1/s] (blocks for its duration)."""
        qs = _check_trajectory(self.robot, qs)
        fps = _check_fps(fps)
        if not (isinstance(repetitions, int) and repetitions >= 1):
            raise ValueError(f"parameter 'repetitions' must be an integer >= 1, got {repetitions!r}")
        start = time.monotonic()
        for rep in range(repetitions):
            for k, q in enumerate(qs):
                self.viz.display(q)
                for name, track in self.forces.items():
                    self._place_force(self.meshcat[f"{ROOT}/forces/{name}"], track, k)
                for node, (positions, shown) in self.marks.items():
                    self.meshcat[f"{ROOT}/{node}"].set_transform(_mark_transform(positions[k], shown[k]))
                wait = start + (rep * len(qs) + k + 1) / fps - time.monotonic()
                if wait > 0:
                    time.sleep(wait)

    def walk_animation(self, qs: np.ndarray, fps: float = 30.0):
        """A meshcat ``Animation`` of the trajectory: one keyframe per row of ``qs``, at ``fps``."""
        from meshcat.animation import Animation

        qs = _check_trajectory(self.robot, qs)
        fps = _check_fps(fps)
        for name, track in self.forces.items():
            if len(track.points) != len(qs):
                raise ValueError(f"force {name!r} has {len(track.points)} frames, the trajectory {len(qs)}")
        anim = Animation(default_framerate=fps)
        for k, q in enumerate(qs):
            with anim.at_frame(self.meshcat, k) as frame:
                for node, T in self.visual_poses(q).items():
                    frame[node].set_transform(T)
                for name, track in self.forces.items():
                    T, length = _arrow_transform(track.points[k], track.forces[k], track.scale)
                    frame[f"{ROOT}/forces/{name}"].set_transform(T)
                    frame[f"{ROOT}/forces/{name}"].set_property("scale", "vector3", [max(length, 1e-6), 1.0, 1.0])
                for node, (positions, shown) in self.marks.items():
                    if len(positions) == len(qs):  # an animation frame carries position and scale apart
                        frame[f"{ROOT}/{node}"].set_transform(_mark_transform(positions[k], True))
                        size = 1.0 if shown[k] else 1e-6
                        frame[f"{ROOT}/{node}"].set_property("scale", "vector3", [size, size, size])
        return anim

    def set_walk_animation(self, qs: np.ndarray, fps: float = 30.0, repetitions: int = 1, play: bool = True):
        """Store the trajectory in the scene as a meshcat animation (what :meth:`static_html` embeds)."""
        if not (isinstance(repetitions, int) and repetitions >= 1):
            raise ValueError(f"parameter 'repetitions' must be an integer >= 1, got {repetitions!r}")
        anim = self.walk_animation(qs, fps)
        self.meshcat.set_animation(anim, play=play, repetitions=repetitions)
        return anim

    def static_html(self) -> str:
        """The whole scene, with its animation, as one self-contained HTML page.

        meshcat's page replays the scene tree's commands in tree order, and the animation sits
        on the root node, so it would come first and the nodes' static poses after it. The
        animation command is moved to the end here, and the ``#t=`` seek script is added.
        """
        import html as html_text

        page = _animation_last(self.meshcat.static_html())
        if self.hud is not None:  # before the insertion point is found: the title changes the length
            page = page.replace("<title>MeshCat</title>", f"<title>{html_text.escape(self.hud.title)}</title>", 1)
        at = page.rfind("</body>")
        if at < 0:
            raise RuntimeError("meshcat's static_html() has no </body>")
        hud = self.hud.script() if self.hud is not None else ""
        return page[:at] + hud + SEEK_SCRIPT + page[at:]

    def close(self) -> None:
        """Stop our server (a reused ``meshcat-server`` keeps running)."""
        if self.server is not None:
            self.server.close()


# --------------------------------------------------------------------------- walks and export


def walk_trajectory(robot, steps: int = 2, samples_per_step: int = 30):
    """The walk to show: :func:`pasibot_pin.kinematics.gait.walk` (stance exchange every half crank turn)."""
    from pasibot_pin.kinematics import gait

    return gait.walk(robot, steps=steps, samples_per_step=samples_per_step)


@dataclass
class Export:
    """What :func:`export_html` wrote.

    Attributes:
        path: the HTML file.
        q: configuration of every animation frame (N, nq); frame k is shown at time k / fps.
        fps: frames per second of the animation [1/s].
        walk: the walk the frames come from.
        paths: the drawn traces ``{name: (N, 3)}`` [m].
        forces: the drawn force arrows ``{name: ForceTrack}``.

    """

    path: Path
    q: np.ndarray
    fps: float
    walk: object
    paths: dict[str, np.ndarray]
    forces: dict = field(default_factory=dict)

    @property
    def duration(self) -> float:
        """Length of one play of the animation [s]."""
        return (len(self.q) - 1) / self.fps


def build_walk_scene(
    viewer: WalkViewer,
    qs: np.ndarray,
    fps: float,
    forces: Mapping[str, ForceTrack] | None = None,
    play: bool = True,
    repetitions: int = LOOP_REPETITIONS,
    title: str | None = None,
    times: np.ndarray | None = None,
    modes: Mapping[str, Sequence[str]] | None = None,
) -> dict[str, np.ndarray]:
    """Ground, foot paths, joint and contact markers, forces, side camera, title bar and the walk animation.

    Args:
        viewer: the viewer to fill.
        qs: the walk (N, nq).
        fps: animation frames per second [1/s].
        forces: optional force arrows (one row per frame).
        play: start the animation as soon as the page has it.
        repetitions: plays of the animation (default: loops practically forever).
        title: the title bar's text (default: the variant); the bar also shows time, crank angle, modes.
        times: each frame's time for the title bar [s] (default: the animation's, k / fps).
        modes: each foot's contact mode per frame (default: from the geometry).

    Returns:
        The drawn traces ``{name: (N, 3)}`` [m].

    """
    paths = viewer.add_foot_paths(qs)
    xs = np.concatenate([p[:, 0] for p in paths.values()])
    margin = 0.4
    viewer.add_ground((float(xs.min()) - margin, float(xs.max()) + margin))
    for name, track in (forces or {}).items():
        viewer.add_force(name, track)
    viewer.add_markers(qs, modes)
    viewer.set_side_camera(qs)
    viewer.display(qs[0])
    viewer.set_walk_animation(qs, fps=fps, repetitions=repetitions, play=play)
    if viewer.robot.floating:
        from pasibot_pin.viz.contacts import foot_contacts

        contacts = foot_contacts(viewer.robot, qs)
        viewer.hud = Hud(
            title=title or f"PASIBOT {viewer.robot.variant} biped",
            fps=fps,
            t=np.arange(len(qs)) / fps if times is None else np.asarray(times, dtype=float),
            theta=contacts.crank,
            modes={s: list(m) for s, m in (modes or contacts.modes).items()},
        )
    return paths


def export_html(
    out: Path | str,
    robot=None,
    *,
    variant: str = "spring",
    steps: int = 2,
    samples_per_step: int = 30,
    fps: float = 30.0,
    force: bool = False,
    show_robot: bool = True,
    forces: Mapping[str, ForceTrack] | None = None,
    ground_reaction: bool = False,
    reactions: float | None = None,
    zmq_url: str | None = None,
) -> Export:
    """Write one self-contained HTML file with the walk animated in meshcat.

    Args:
        out: the HTML file to write.
        robot: a two-legged robot; ``None`` loads ``variant``.
        variant: leg variant when ``robot`` is ``None``.
        steps: number of steps (half crank turns).
        samples_per_step: animation frames per step.
        fps: animation frames per second [1/s].
        force: overwrite an existing file.
        show_robot: ``False`` hides the robot (ground and paths only; a reference picture).
        forces: optional force arrows, one :class:`ForceTrack` per name, one row per frame.
        ground_reaction: add the quasi-static ground reaction arrow
            (:func:`quasi_static_ground_reaction`, 0.5 mm per N).
        reactions: crank speed [rad/s] at which to draw the ground reaction and the cut-joint
            forces of :func:`reaction_forces` (``spring`` only); ``None``: none.
        zmq_url: build the scene on a running meshcat server (default: in this process, no server).

    Returns:
        The :class:`Export`.

    Raises:
        FileExistsError: ``out`` exists and ``force`` is false.
        ValueError: bad arguments.

    """
    out = Path(out)
    if out.exists() and not force:
        raise FileExistsError(f"{out} exists; pass force=True (--force) to overwrite it")
    if out.suffix.lower() not in (".html", ".htm"):
        raise ValueError(f"parameter 'out' must end in .html, got {out}")
    fps = _check_fps(fps)
    if robot is None:
        from pasibot_pin.model.robot import load

        robot = load(variant, legs=2)
    walk = walk_trajectory(robot, steps=steps, samples_per_step=samples_per_step)
    if ground_reaction:
        forces = {**(forces or {}), "ground": quasi_static_ground_reaction(robot, walk.q, walk.stance)}
    if reactions is not None:
        forces = {**(forces or {}), **reaction_forces(robot, walk, omega=reactions)}
    viewer = WalkViewer(robot, zmq_url=zmq_url, offline=zmq_url is None)
    try:
        title = f"PASIBOT {robot.variant} biped, {steps} steps (kinematic walk, stance sole welded flat)"
        paths = build_walk_scene(viewer, walk.q, fps, forces, title=title)
        viewer.show_robot(show_robot)
        if not show_robot:  # a reference picture: no title bar either
            viewer.hud = None
        html = viewer.static_html()
    finally:
        viewer.close()
    from pasibot_pin.files import write_text_atomic

    write_text_atomic(out, html)
    return Export(path=out, q=walk.q.copy(), fps=fps, walk=walk, paths=paths, forces=dict(forces or {}))
