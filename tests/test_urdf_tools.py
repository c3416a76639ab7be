"""The committed URDFs load, unedited, in the tools people use: MuJoCo, urdfdom's check_urdf, yourdfpy.

And a design's two exports, ``build-urdf --design F`` and ``export-mjcf --design F``, carry the same
bodies: every moving body's mass, centre of mass and rotational inertia agree (MuJoCo reads both;
Pinocchio reads the URDF's inertias as they are written, with no mass rule applied).
"""

from __future__ import annotations

import shutil
import subprocess
import xml.etree.ElementTree as ET
from pathlib import Path

import mujoco
import numpy as np
import pytest

from pasibot_pin.__main__ import main
from pasibot_pin.model.description import build_tree
from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.model.mjcf import SPRING_STEP_RATIO
from pasibot_pin.model.paths import URDF_DIR

pytestmark = [pytest.mark.integration]

COMMITTED = sorted(URDF_DIR.glob("pasibot_*.urdf"))
BOUND = 1e-8
"""MuJoCo's ``boundinertia`` in both exports [kg.m^2]: a point mass's inertia reads this much."""


def _urdf_masses(path: Path) -> dict[str, float]:
    return {
        link.get("name"): float(link.find("inertial/mass").get("value"))
        for link in ET.parse(path).getroot().iter("link")
        if link.find("inertial/mass") is not None
    }


def test_six_committed_urdfs():
    assert len(COMMITTED) == 6


@pytest.mark.parametrize("path", COMMITTED, ids=lambda p: p.stem)
def test_committed_urdf_loads_in_mujoco(path):
    model = mujoco.MjModel.from_xml_path(str(path))
    root = ET.parse(path).getroot()
    revolute = [j.get("name") for j in root.iter("joint") if j.get("type") in ("revolute", "prismatic")]
    assert model.njnt == len(revolute)
    assert {model.joint(k).name for k in range(model.njnt)} == set(revolute)
    assert model.nbody - 1 == len(list(root.iter("link")))  # every link a body (marker frames kept)
    assert float(np.sum(model.body_mass)) == pytest.approx(sum(_urdf_masses(path).values()), rel=1e-12)
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    assert np.all(np.isfinite(data.qacc))


def _check_urdf() -> str:
    tool = shutil.which("check_urdf") or ("/usr/bin/check_urdf" if Path("/usr/bin/check_urdf").is_file() else None)
    assert tool, "check_urdf is missing: `make urdf-tools` installs Debian's liburdfdom-tools"
    return tool


@pytest.mark.parametrize("path", COMMITTED, ids=lambda p: p.stem)
def test_committed_urdf_passes_check_urdf(path):
    done = subprocess.run([_check_urdf(), str(path)], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "Successfully Parsed XML" in done.stdout
    assert "root Link: hip" in done.stdout
    assert "Error" not in done.stdout + done.stderr


@pytest.mark.parametrize("path", COMMITTED, ids=lambda p: p.stem)
def test_committed_urdf_loads_in_yourdfpy(path):
    import yourdfpy  # deferred: 1.4 s of imports (trimesh, networkx), paid by every worker that collects this module

    robot = yourdfpy.URDF.load(str(path), load_meshes=False, build_collision_scene_graph=False)
    assert robot.validate()
    root = ET.parse(path).getroot()
    assert set(robot.link_map) == {link.get("name") for link in root.iter("link")}
    assert robot.base_link == "hip"
    for name, mass in _urdf_masses(path).items():
        assert robot.link_map[name].inertial.mass == mass


# --------------------------------------------------------------------------- the two exports agree


def _rotation(quat: np.ndarray) -> np.ndarray:
    matrix = np.zeros(9)
    mujoco.mju_quat2Mat(matrix, quat)
    return matrix.reshape(3, 3)


def _body_inertia(model, b: int) -> tuple[float, np.ndarray, np.ndarray]:
    """(mass, COM, 3x3 inertia about the COM), in body ``b``'s own frame."""
    rot = _rotation(model.body_iquat[b])
    return float(model.body_mass[b]), model.body_ipos[b].copy(), rot @ np.diag(model.body_inertia[b]) @ rot.T


def _lumped(model, b: int) -> tuple[float, np.ndarray, np.ndarray]:
    """Body ``b`` and every body welded to it (no joint between), as one body in ``b``'s frame."""
    parts = []  # (mass, com, inertia at com, rotation, translation) in b's frame

    def visit(k: int, rotation: np.ndarray, translation: np.ndarray) -> None:
        m, c, inertia = _body_inertia(model, k)
        parts.append((m, rotation @ c + translation, rotation @ inertia @ rotation.T))
        for child in range(model.nbody):
            if model.body_parentid[child] == k and child != k and model.body_jntnum[child] == 0:
                r = _rotation(model.body_quat[child])
                visit(child, rotation @ r, rotation @ model.body_pos[child] + translation)

    visit(b, np.eye(3), np.zeros(3))
    mass = sum(m for m, _, _ in parts)
    com = sum(m * c for m, c, _ in parts) / mass
    inertia = np.zeros((3, 3))
    for m, c, i in parts:
        d = c - com
        inertia += i + m * (d @ d * np.eye(3) - np.outer(d, d))
    return mass, com, inertia


def _spring_stiffness(model) -> float:
    """The stiffest joint spring of a MuJoCo model [N.m/rad] (0 without springs)."""
    return float(np.max(model.jnt_stiffness)) if model.njnt else 0.0


@pytest.mark.parametrize("inertia", ["uniform", "point"])
@pytest.mark.parametrize("variant", ["spring", "rigid", "parallel"])
def test_urdf_and_mjcf_of_one_design_agree_on_every_body(variant, inertia, tmp_path, capsys):
    design = Design(variant=variant, inertia=inertia, K=2.2, body_com_dx=0.02)
    design_file = design.save(tmp_path / "design.toml")
    urdf, mjcf = tmp_path / "robot.urdf", tmp_path / "robot.xml"
    assert main(["build-urdf", "--design", str(design_file), "--out", str(urdf)]) == 0
    assert main(["export-mjcf", "--design", str(design_file), "--out", str(mjcf)]) == 0

    # Pinocchio on the URDF as written (no mass rule): the design's robot, joint by joint, to round-off
    robot = design_robot(design, 2)
    written = build_tree(urdf.read_text(), 2)
    for j in range(1, robot.model.njoints):
        expected, got = robot.model.inertias[j], written.inertias[written.getJointId(robot.model.names[j])]
        assert got.mass == pytest.approx(expected.mass, rel=1e-12), robot.model.names[j]
        np.testing.assert_allclose(got.lever, expected.lever, atol=1e-12)
        np.testing.assert_allclose(got.inertia, expected.inertia, atol=1e-12)

    # MuJoCo on both files: each MJCF body (one per Pinocchio joint) against the URDF's links welded together
    from_urdf, from_mjcf = mujoco.MjModel.from_xml_path(str(urdf)), mujoco.MjModel.from_xml_path(str(mjcf))
    hip = next(b for b in range(1, from_urdf.nbody) if from_urdf.body_parentid[b] == 0)
    assert from_urdf.body(hip).name == "hip"
    compared = 0
    for b in range(1, from_mjcf.nbody):
        if from_mjcf.body_jntnum[b] == 0:
            continue
        joint = from_mjcf.joint(int(from_mjcf.body_jntadr[b])).name
        if joint in [from_urdf.joint(k).name for k in range(from_urdf.njnt)]:
            k = int(from_urdf.joint(joint).bodyid[0])
        else:  # the planar root joint's body is the hip (the URDF's root link, welded to the world there)
            k = hip
        m_u, c_u, i_u = _lumped(from_urdf, k)
        m_m, c_m, i_m = _body_inertia(from_mjcf, b)
        assert m_u == pytest.approx(m_m, rel=1e-12), joint
        np.testing.assert_allclose(c_u, c_m, atol=1e-12, err_msg=joint)
        # MuJoCo bounds point masses: the URDF at BOUND, the MJCF at what its stiffest spring needs to stay
        # stable at its time step (mjcf.stable_boundinertia): the bodies agree above the larger bound
        bound = max(BOUND, float(from_mjcf.opt.timestep) ** 2 * _spring_stiffness(from_mjcf) / SPRING_STEP_RATIO)
        np.testing.assert_allclose(np.maximum(i_u, bound), np.maximum(i_m, bound), atol=10 * BOUND, err_msg=joint)
        if inertia == "uniform" and m_m > 0 and from_urdf.body(k).name.rsplit("_", 1)[-1] != "slider":
            assert np.max(i_m) > 100 * BOUND  # rods and the hip box: real inertias (the slider is a point mass)
        compared += 1
    assert compared == robot.model.njoints - 1
    assert float(np.sum(from_urdf.body_mass)) == pytest.approx(float(np.sum(from_mjcf.body_mass)), rel=1e-12)
