"""The meshcat viewer: loopback-only server, the exported animation's poses, colours, forces, CLI.

The exported HTML is decoded here (base64 msgpack commands, as meshcat's page reads them), so
the checks are on what a browser receives, not on the Python objects that produced it.
"""

from __future__ import annotations

import base64
import re
import subprocess
import sys
import urllib.request

import numpy as np
import pinocchio as pin
import pytest
import umsgpack
from meshcat_checks import decode_commands
from report_checks import assert_reads_like_a_report

from pasibot_pin.__main__ import main
from pasibot_pin.model import closure
from pasibot_pin.viz import viewer
from pasibot_pin.viz.plots import GROUP_COLOURS, link_group

pytestmark = [pytest.mark.network]

LOOPBACK_HEX = "0100007F"  # 127.0.0.1 as /proc/net/tcp prints it (little-endian)


# --------------------------------------------------------------------------- helpers


def listening_addresses(port: int) -> set[str]:
    """Local addresses of the sockets LISTENing on TCP ``port``, from /proc/net/tcp{,6}."""
    found = set()
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        try:
            lines = open(table).read().splitlines()[1:]
        except FileNotFoundError:
            continue
        for line in lines:
            fields = line.split()
            address, port_hex = fields[1].split(":")
            if fields[3] == "0A" and int(port_hex, 16) == port:  # 0A = LISTEN
                found.add(address)
    return found


def without_uuids(commands: list[dict]) -> list:
    """``commands`` with every meshcat uuid (uuid1: time-based) replaced by its order of appearance."""
    pattern = re.compile(r"^[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}$")
    seen: dict[str, str] = {}

    def walk(value):
        if isinstance(value, dict):
            return {k: walk(v) for k, v in value.items()}
        if isinstance(value, list):
            return [walk(v) for v in value]
        if isinstance(value, str) and pattern.match(value):
            return seen.setdefault(value, f"uuid-{len(seen)}")
        return value

    return walk(commands)


def animation_poses(commands: list[dict]) -> tuple[dict[str, list[np.ndarray]], dict]:
    """Per animated node path: the 4x4 pose at each keyframe; and the raw clip dicts."""
    anims = [c for c in commands if c["type"] == "set_animation"]
    assert len(anims) == 1
    poses, clips = {}, {}
    for entry in anims[0]["animations"]:
        clip = entry["clip"]
        clips[entry["path"]] = clip
        tracks = {t["name"]: t for t in clip["tracks"]}
        if ".position" not in tracks:
            continue
        out = []
        for kp, kq in zip(tracks[".position"]["keys"], tracks[".quaternion"]["keys"]):
            assert kp["time"] == kq["time"]
            x, y, z, w = kq["value"]
            T = np.eye(4)
            T[:3, :3] = pin.Quaternion(w, x, y, z).toRotationMatrix()
            T[:3, 3] = kp["value"]
            out.append(T)
        poses[entry["path"]] = out
    return poses, clips


@pytest.fixture(scope="module")
def robot():
    import pasibot_pin as pp

    return pp.load("spring", legs=2)


@pytest.fixture(scope="module")
def exported(robot, tmp_path_factory):
    out = tmp_path_factory.mktemp("export") / "walk.html"
    export = viewer.export_html(out, robot, steps=2, samples_per_step=10, fps=20.0)
    return export, out.read_text()


@pytest.fixture(scope="module")
def server():
    srv = viewer.start_server()
    yield srv
    srv.close()


# --------------------------------------------------------------------------- server


def test_own_server_listens_on_loopback_only(server):
    assert server.web_url.startswith("http://127.0.0.1:")
    assert server.zmq_url.startswith("tcp://127.0.0.1:")
    for port in (server.web_port, server.zmq_port):
        addresses = listening_addresses(port)
        assert addresses == {LOOPBACK_HEX}, (port, addresses)
    page = urllib.request.urlopen(server.web_url, timeout=10).read().decode()
    assert "main.min.js" in page  # it is meshcat's page


def test_stock_meshcat_server_listens_on_all_interfaces():
    """The premise (and a check that listening_addresses can see a wildcard bind)."""
    from meshcat.servers.zmqserver import start_zmq_server_as_subprocess

    proc, _zmq_url, web_url = start_zmq_server_as_subprocess()
    try:
        port = int(web_url.split(":")[2].split("/")[0])
        addresses = listening_addresses(port)
        assert addresses and addresses != {LOOPBACK_HEX}, addresses
        assert addresses & {"00000000", "00000000000000000000000000000000"}
    finally:
        proc.kill()
        proc.wait()


def test_reuses_a_running_server_and_leaves_it_running(robot, server):
    v = viewer.WalkViewer(robot, zmq_url=server.zmq_url)
    assert v.server is None
    assert v.url == server.web_url
    html = v.jupyter_cell(height=300).data
    assert server.web_url in html and "iframe" in html
    v.close()
    assert server.process.poll() is None


def test_offline_scene_gives_the_server_page(robot, exported, tmp_path):
    """export_html builds its scene in-process (no server); a fresh server's page is the same."""
    export, offline_html = exported
    out = tmp_path / "via_server.html"
    server = viewer.start_server()  # fresh: a server keeps the scenes of its earlier clients
    try:
        viewer.export_html(out, robot, steps=2, samples_per_step=10, fps=20.0, zmq_url=server.zmq_url)
    finally:
        server.close()
    served_html = out.read_text()
    blob = r"data:application/octet-binary;base64,[A-Za-z0-9+/=]+"
    assert re.sub(blob, "", served_html) == re.sub(blob, "", offline_html)  # the page around the commands
    served, offline = decode_commands(served_html), decode_commands(offline_html)
    assert len(offline) > 50  # a whole scene, not an empty page
    assert without_uuids(served) == without_uuids(offline)  # the same commands in the same order
    with pytest.raises(ValueError, match="offline"):
        viewer.WalkViewer(robot, offline=True, open=True)


def test_command_type_read_from_the_first_bytes_is_msgpacks(exported):
    """The exported page's commands: the type read off each one's first bytes is the unpacked one's."""
    _, html = exported
    blobs = [base64.b64decode(b) for b in re.findall(r"data:application/octet-binary;base64,([A-Za-z0-9+/=]+)", html)]
    types = [viewer.command_type(b) for b in blobs]
    assert types == [umsgpack.unpackb(b)["type"] for b in blobs]
    assert {"set_object", "set_transform", "set_property", "set_animation"} <= set(types)
    assert types[-1] == "set_animation"  # moved after the static poses
    assert viewer.command_type(umsgpack.packb({"path": "/x", "type": "delete"})) == "delete"  # another key order


def test_bad_zmq_url(robot):
    with pytest.raises(ValueError, match="zmq_url"):
        viewer.WalkViewer(robot, zmq_url="localhost:6000")


# --------------------------------------------------------------------------- exported animation


def test_exported_frames_satisfy_the_loops(robot, exported):
    export, _ = exported
    walk = export.gait
    assert export.q.shape == (2 * 10 + 1, robot.model.nq)
    worst_loops, worst_all = 0.0, 0.0
    for k, q in enumerate(export.q):
        worst_loops = max(worst_loops, np.abs(closure.constraint_residual(robot, q, robot.loop_constraints)).max())
        contacts = walk.contacts[walk.step[k]]
        worst_all = max(worst_all, np.abs(closure.constraint_residual(robot, q, contacts)).max())
    assert worst_loops < 1e-9
    assert worst_all < 1e-9
    # the walk moves: frames are not all one pose, and the hip advances
    assert np.ptp(export.q[:, 0]) > 0.2


def test_html_animation_closes_the_loops(robot, exported):
    """Rebuild each cut joint from the animated link poses in the HTML: both sides coincide."""
    export, html = exported
    poses, clips = animation_poses(decode_commands(html))
    model = robot.model
    n = len(export.q)
    by_joint = {}
    for obj in robot.visual_model.geometryObjects:
        path = f"/meshcat/{viewer.ROOT}/visuals/{obj.name}"
        assert len(poses[path]) == n
        by_joint[obj.parentJoint] = (path, obj.placement)
    for clip in clips.values():
        assert clip["fps"] == pytest.approx(20.0)
    worst = 0.0
    for loop in robot.loops:
        for k in range(n):
            points = []
            for frame_name in (loop.frame_a, loop.frame_b):
                frame = model.frames[model.getFrameId(frame_name)]
                path, g_in_joint = by_joint[frame.parentJoint]
                oMj = pin.SE3(poses[path][k]) * g_in_joint.inverse()
                points.append((oMj * frame.placement).translation)
            worst = max(worst, np.linalg.norm(points[0] - points[1]))
    assert worst < 1e-9
    # the stance foot does not move during a step
    for side in ("right", "left"):
        path = f"/meshcat/{viewer.ROOT}/visuals/{side}_foot_0"
        stance = [k for k in range(n) if export.gait.stance[k] == side]
        assert stance
        p = np.array([poses[path][k][:3, 3] for k in stance if export.gait.step[k] == export.gait.step[stance[0]]])
        assert np.ptp(p, axis=0).max() < 1e-9
        assert abs(p[:, 2].mean()) < 0.05  # on the ground


def test_html_matches_the_returned_configurations(robot, exported):
    export, html = exported
    poses, _ = animation_poses(decode_commands(html))
    data = robot.model.createData()
    gdata = pin.GeometryData(robot.visual_model)
    for k in (0, len(export.q) // 2, len(export.q) - 1):
        pin.forwardKinematics(robot.model, data, export.q[k])
        pin.updateGeometryPlacements(robot.model, data, robot.visual_model, gdata)
        for gid, obj in enumerate(robot.visual_model.geometryObjects):
            np.testing.assert_allclose(
                poses[f"/meshcat/{viewer.ROOT}/visuals/{obj.name}"][k], gdata.oMg[gid].homogeneous, atol=1e-12
            )


def test_html_is_self_contained_with_group_colours_paths_and_ground(robot, exported):
    _, html = exported
    assert "<script src=" not in html and "http://" not in html.split("<script>")[0]
    assert "new MeshCat.Viewer" in html and viewer.SEEK_SCRIPT.strip() in html
    # the seek wraps the viewer's commands before the first is fetched: a fetch's callback may run as soon as the
    # parser yields, and the animation handled before the wrap would play instead of pausing at #t=
    made = html.index("new MeshCat.Viewer")
    assert made < html.index(viewer.SEEK_SCRIPT.strip()) < html.index('fetch("data:') > made
    objects = {c["path"]: c["object"] for c in decode_commands(html) if c["type"] == "set_object"}
    for obj in robot.visual_model.geometryObjects:
        group = link_group(robot.model.frames[obj.parentFrame].name)
        material = objects[f"/meshcat/{viewer.ROOT}/visuals/{obj.name}"]["materials"][0]
        assert material["color"] == int(GROUP_COLOURS[group][1:], 16), obj.name
    assert f"/meshcat/{viewer.ROOT}/ground" in objects
    for name in ("right", "left", "hip"):
        line = objects[f"/meshcat/{viewer.ROOT}/paths/{name}"]
        assert line["object"]["type"] == "Line"


def test_animation_is_replayed_after_the_static_poses(exported):
    """meshcat stores the animation on the root node (replayed first); the export moves it last."""
    _, html = exported
    types = [c["type"] for c in decode_commands(html)]
    assert types.count("set_animation") == 1
    assert types[-1] == "set_animation"
    assert "set_transform" in types[:-1]


def test_ground_slab_sits_under_the_foot_boxes(robot, exported, L):
    """The URDF's foot box (0.1 L thick) hangs below the sole; the slab's top is there."""
    _, html = exported
    assert viewer.sole_depth(robot) == pytest.approx(0.1 * L, abs=1e-12)
    transforms = {c["path"]: c["matrix"] for c in decode_commands(html) if c["type"] == "set_transform"}
    ground = np.array(transforms[f"/meshcat/{viewer.ROOT}/ground"]).reshape(4, 4).T  # column-major
    assert ground[2, 3] + viewer.GROUND_THICKNESS / 2 == pytest.approx(-0.1 * L, abs=1e-7)


def test_quasi_static_ground_reaction_is_the_weight_below_the_com(robot, exported):
    export, _ = exported
    walk = export.gait
    track = viewer.quasi_static_ground_reaction(robot, walk.q, walk.stance)
    model = robot.model
    data = model.createData()
    assert np.linalg.norm(model.gravity.linear) == pytest.approx(9.81)
    for k in (0, 7, 15, 20):
        pin.forwardKinematics(model, data, walk.q[k])
        masses = np.array([model.inertias[i].mass for i in range(model.njoints)])
        coms = np.array([data.oMi[i].act(model.inertias[i].lever) for i in range(model.njoints)])
        np.testing.assert_allclose(track.forces[k], [0.0, 0.0, 9.81 * masses.sum()], rtol=1e-12)
        assert track.points[k][0] == pytest.approx(masses @ coms[:, 0] / masses.sum(), abs=1e-12)
        assert track.points[k][2] == 0.0
        assert track.points[k][1] == pytest.approx(-0.1 if walk.stance[k] == "right" else 0.1, abs=1e-9)
    with pytest.raises(ValueError, match="stance"):
        viewer.quasi_static_ground_reaction(robot, walk.q, walk.stance[:-1])


def test_dynamics_ground_reaction_agrees_with_the_weight_below_the_com(robot, exported):
    """Two independent routes at omega = 0: constrained inverse dynamics vs the COM."""
    from pasibot_pin.dynamics import inverse as dynamics

    walk = exported[0].gait
    tracks = viewer.reaction_forces(robot, walk, omega=0.0)
    simple = viewer.quasi_static_ground_reaction(robot, walk.q, walk.stance)
    np.testing.assert_allclose(tracks["ground"].forces, simple.forces, atol=1e-9)
    np.testing.assert_allclose(tracks["ground"].points[:, [0, 2]], simple.points[:, [0, 2]], atol=1e-9)
    same_stance = [k for k in range(walk.n) if dynamics.stance_side(walk.theta[k]) == walk.stance[k]]
    assert len(same_stance) >= walk.n - 1
    np.testing.assert_allclose(tracks["ground"].points[same_stance], simple.points[same_stance], atol=1e-9)


def test_cut_force_arrows_sit_on_the_cut_joints(robot, exported):
    walk = exported[0].gait
    tracks = viewer.reaction_forces(robot, walk, omega=np.pi)
    cuts = {name: t for name, t in tracks.items() if name != "ground"}
    assert set(cuts) == {f"{role}_j{j}" for role in ("stance", "swing") for j in (2, 5, 7)}
    longest = max(np.linalg.norm(t.forces, axis=1).max() * t.scale for t in cuts.values())
    assert longest == pytest.approx(0.15)
    data = robot.model.createData()
    for k in (0, 12):
        pin.framesForwardKinematics(robot.model, data, walk.q[k])
        swing = "left" if walk.stance[k] == "right" else "right"
        for name, track in cuts.items():
            role, joint = name.split("_", 1)
            leg = walk.stance[k] if role == "stance" else swing
            b = data.oMf[robot.frame_id(f"{leg}_loop_{joint}_b")].translation
            np.testing.assert_allclose(track.points[k], b, atol=1e-9)  # the cut joint, from either side
            assert track.forces[k][1] == 0.0 and np.linalg.norm(track.forces[k]) > 1.0


def test_foot_paths_follow_the_ankles(robot, exported):
    export, _ = exported
    right = export.gait.positions("right_foot")
    np.testing.assert_allclose(export.paths["right"], right, atol=1e-12)
    # a stance ankle stays put, the swing ankle lifts
    assert np.ptp(right[:11, 0]) < 1e-9
    assert export.paths["left"][:11, 2].max() > 0.05


def test_export_refuses_to_overwrite(robot, tmp_path, capsys):
    out = tmp_path / "mine.html"
    out.write_text("keep me")
    with pytest.raises(FileExistsError):
        viewer.export_html(out, robot, steps=1, samples_per_step=3)
    assert main(["export-html", "--out", str(out), "--steps", "1", "--samples-per-step", "3"]) == 2
    assert "--force" in capsys.readouterr().err
    assert out.read_text() == "keep me"
    assert main(["export-html", "--out", str(out), "--steps", "1", "--samples-per-step", "3", "--force"]) == 0
    assert "new MeshCat.Viewer" in out.read_text()


def test_export_rejects_bad_input(robot, tmp_path):
    with pytest.raises(ValueError, match="fps"):
        viewer.export_html(tmp_path / "a.html", robot, fps=0.0)
    with pytest.raises(ValueError, match="out"):
        viewer.export_html(tmp_path / "a.txt", robot)
    assert not list(tmp_path.iterdir())


def test_export_html_cli_with_ground_reaction(tmp_path, capsys):
    out = tmp_path / "g.html"
    assert main(["export-html", "--out", str(out), "--steps", "1", "--samples-per-step", "4", "--ground-reaction"]) == 0
    assert "5 frames at 30 fps" in capsys.readouterr().out
    paths = {
        entry["path"]
        for c in decode_commands(out.read_text())
        if c["type"] == "set_animation"
        for entry in c["animations"]
    }
    assert f"/meshcat/{viewer.ROOT}/forces/ground" in paths


# --------------------------------------------------------------------------- forces, live play, CLI


def test_force_arrows_are_scaled_and_aimed(robot, server):
    v = viewer.WalkViewer(robot, zmq_url=server.zmq_url)
    qs = np.array([robot.q0, robot.q0, robot.q0])
    points = np.array([[0.0, 0.0, 0.0], [0.1, 0.0, 0.0], [0.2, 0.0, 0.05]])
    forces = np.array([[0.0, 0.0, 400.0], [30.0, 0.0, 300.0], [-50.0, 0.0, 120.0]])
    scale = 1e-3
    v.add_force("ground", viewer.ForceArrows(points, forces, scale))
    anim = v.walk_animation(qs, fps=10.0)
    lowered = {entry["path"]: entry["clip"] for entry in anim.lower()}
    tracks = {t["name"]: t["keys"] for t in lowered[f"/meshcat/{viewer.ROOT}/forces/ground"]["tracks"]}
    for k in range(3):
        length = tracks[".scale"][k]["value"][0]
        assert length == pytest.approx(np.linalg.norm(forces[k]) * scale, rel=1e-12)
        np.testing.assert_allclose(tracks[".position"][k]["value"], points[k], atol=1e-15)
        x, y, z, w = tracks[".quaternion"][k]["value"]
        tip = pin.Quaternion(w, x, y, z).toRotationMatrix() @ np.array([length, 0.0, 0.0])
        np.testing.assert_allclose(tip, forces[k] * scale, atol=1e-12)
    with pytest.raises(ValueError, match="frames"):
        v.walk_animation(qs[:2], fps=10.0)
    with pytest.raises(ValueError, match="scale"):
        viewer.ForceArrows(points, forces, -1.0)
    v.play(qs, fps=200.0)  # live: sends the frames (arrows included) and returns
    v.close()


def test_view_command_plays_once_and_exits():
    proc = subprocess.run(
        [sys.executable, "-m", "pasibot_pin", "view", "--steps", "1", "--samples-per-step", "4", "--fps", "40"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 0, proc.stderr
    assert "viewer: http://127.0.0.1:" in proc.stdout
    assert "playing 1 step (5 frames" in proc.stdout


def test_view_command_with_reactions_live(capsys):
    args = ["view", "--steps", "1", "--samples-per-step", "3", "--fps", "60", "--reactions", "1.0"]
    assert main(args) == 0
    assert "viewer: http://127.0.0.1:" in capsys.readouterr().out


def test_analyze_step_writes_gait_html_and_gif(tmp_path):
    from PIL import Image

    from pasibot_pin.report import animation

    section = animation.section(tmp_path)
    assert (tmp_path / "gait.html").stat().st_size > 500_000
    with Image.open(tmp_path / "gait.gif") as gif:
        assert gif.n_frames == 2 * 30 // 2 + 1  # 2 steps of 30 samples, every other one
        assert gif.info["duration"] == pytest.approx(1000 / 15, abs=10)  # 15 fps: the HTML's 30 fps speed
    assert "(gait.html)" in section and "(gait.gif)" in section
    assert_reads_like_a_report(tmp_path, section, 1)
    forces = {
        entry["path"]
        for c in decode_commands((tmp_path / "gait.html").read_text())
        if c["type"] == "set_animation"
        for entry in c["animations"]
    }
    assert f"/meshcat/{viewer.ROOT}/forces/ground" in forces


def test_view_rejects_bad_options(capsys):
    assert main(["view", "--repeat", "0"]) == 2
    assert "--repeat" in capsys.readouterr().err


# --------------------------------------------------------------------------- hip, joints, contacts, title bar
def _clip_tracks(html: str) -> dict[str, dict]:
    anims = [c for c in decode_commands(html) if c["type"] == "set_animation"]
    return {e["path"]: {t["name"]: t["keys"] for t in e["clip"]["tracks"]} for e in anims[0]["animations"]}


def _hud_info(html: str) -> dict:
    import json

    match = re.search(r"var info = (\{.*?\});\n", html)
    assert match, "no title bar in the page"
    return json.loads(match.group(1))


def test_hip_is_see_through_and_the_rest_opaque(robot, exported):
    _, html = exported
    objects = {c["path"]: c["object"] for c in decode_commands(html) if c["type"] == "set_object"}
    for obj in robot.visual_model.geometryObjects:
        material = objects[f"/meshcat/{viewer.ROOT}/visuals/{obj.name}"]["materials"][0]
        if link_group(robot.model.frames[obj.parentFrame].name) == "hip":
            assert material["transparent"] and material["opacity"] == pytest.approx(viewer.HIP_OPACITY)
            assert viewer.HIP_OPACITY < 0.5
        else:
            assert not material.get("transparent", False), obj.name


def test_joint_markers_sit_on_the_joints_and_close_the_loops(robot, exported):
    """Each marker is at its joint in every frame; the two markers of a cut joint's sides coincide."""
    export, html = exported
    tracks = _clip_tracks(html)
    marks = {p.rsplit("/", 1)[-1]: t for p, t in tracks.items() if "/joints/" in p}
    assert set(marks) >= {robot.model.names[j] for j in range(1, robot.model.njoints)}
    assert sum(name.endswith("_a") and "_loop_" in name for name in marks) == len(robot.loops)
    data = robot.model.createData()
    for k in (0, len(export.q) // 2):
        pin.framesForwardKinematics(robot.model, data, export.q[k])
        for j in range(1, robot.model.njoints):
            np.testing.assert_allclose(marks[robot.model.names[j]][".position"][k]["value"], data.oMi[j].translation)
        for loop in robot.loops:  # the marker at side a is where side b's frame is: the loop is closed
            b = data.oMf[robot.model.getFrameId(loop.frame_b)].translation
            np.testing.assert_allclose(marks[loop.frame_a][".position"][k]["value"], b, atol=1e-9)


def test_contact_points_show_the_stance_sole_on_the_ground(robot, exported):
    export, html = exported
    tracks = _clip_tracks(html)
    walk, n = export.gait, len(export.q)
    for side in ("right", "left"):
        for point in ("heel", "toe"):
            keys = tracks[f"/meshcat/{viewer.ROOT}/contacts/{side}_{point}"]
            shown = [keys[".scale"][k]["value"][0] == 1.0 for k in range(n)]
            z = [keys[".position"][k]["value"][2] for k in range(n)]
            for k in range(n):
                if walk.stance[k] == side:  # the welded sole: both points on the ground, shown
                    assert shown[k] and abs(z[k]) < 1e-9, (side, point, k)
                if shown[k]:
                    assert abs(z[k]) <= 1e-3
            assert not all(shown), f"the {side} foot swings: its {point} leaves the ground"


def test_title_bar_shows_the_time_crank_angle_and_modes(robot, exported):
    export, html = exported
    info = _hud_info(html)
    walk, n = export.gait, len(export.q)
    assert info["title"].startswith("PASIBOT spring biped") and f"<title>{info['title']}</title>" in html
    assert info["fps"] == pytest.approx(export.fps) and len(info["t"]) == len(info["theta"]) == n
    np.testing.assert_allclose(info["t"], np.arange(n) / export.fps, atol=1e-6)
    np.testing.assert_allclose(info["theta"], np.degrees(walk.theta), atol=1e-3)  # the gait's own crank angles
    for k in range(n):
        assert info["modes"][walk.stance[k]][k] == "flat"
    assert {"air"} <= set(info["modes"]["right"]) | set(info["modes"]["left"])
    assert 'id="pasibot-hud"' in html


def test_foot_modes_from_the_sole_heights():
    from pasibot_pin.viz.contacts import mode_of

    assert mode_of(0.0, 0.0) == "flat"
    assert mode_of(0.0, 0.05) == "heel" and mode_of(0.05, 0.0005) == "toe"
    assert mode_of(0.02, 0.03) == "air" and mode_of(-0.01, 0.0) == "below ground"


def test_gif_frames_draw_the_contacts_and_the_ground_reaction(robot):
    from pasibot_pin.viz import animation as stick
    from pasibot_pin.viz.contacts import foot_contacts

    walk = viewer.gait_trajectory(robot, steps=1, samples_per_step=4)
    track = viewer.quasi_static_ground_reaction(robot, walk.q, walk.stance)

    def colour_pixels(image, colour: str) -> int:
        rgb = np.asarray(image.convert("RGB")).astype(int)
        target = np.array([int(colour[i : i + 2], 16) for i in (1, 3, 5)])
        return int(np.sum(np.abs(rgb - target).sum(axis=2) < 60))

    plain = stick.stick_frames(robot, walk.q[:1].repeat(2, axis=0), fps=10.0)
    marked = stick.stick_frames(
        robot,
        walk.q[:1].repeat(2, axis=0),
        fps=10.0,
        forces={"ground": type(track)(track.points[:2], track.forces[:2], track.scale)},
    )
    assert sum(foot_contacts(robot, walk.q[:1]).touching["right"][0]) == 2
    assert colour_pixels(plain[0], stick.CONTACT_COLOUR) > 20  # the two sole points
    assert colour_pixels(marked[0], viewer.FORCE_COLOUR) > colour_pixels(plain[0], viewer.FORCE_COLOUR) + 5  # the arrow


def test_the_walk_pages_camera_follows_the_hip():
    """Issue 34: with ``follow`` the scene is shifted by minus the hip's x in every animation frame (the hip stays
    mid-view) and the camera stands at a robot's height, not at the width of the whole walk."""
    from pasibot_pin.model.coordinates import HIP_X
    from pasibot_pin.model.design import Design, design_robot

    robot = design_robot(Design(variant="parallel"), 2, visuals=True)
    qs = np.repeat(robot.q0[None], 6, axis=0)
    qs[:, HIP_X] = 2.0 * np.arange(6)  # a 10 m walk
    v = viewer.WalkViewer(robot, offline=True)
    try:
        v.set_side_camera(qs)
        assert v.follow is None
        assert not any(p.lower().rstrip("/").endswith(f"/{viewer.ROOT}") for p in v.walk_animation(qs).clips)
        v.set_side_camera(qs, follow=True)
        anim = v.walk_animation(qs, fps=10.0)
        clip = next(c for p, c in anim.clips.items() if p.lower().rstrip("/").endswith(f"/{viewer.ROOT}"))
        shifts = [value[:3] if len(value) == 3 else value for value in clip.tracks["position"].values]
        assert [s[0] for s in shifts] == pytest.approx(list(-qs[:, HIP_X]))
        assert len({tuple(np.round(s[1:], 12)) for s in shifts}) == 1  # y and z held: only x follows
    finally:
        v.close()
