"""The committed URDFs: generated from the xacro source, strict trees, same kinematics in yourdfpy."""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import pinocchio as pin
import pytest
from conftest import ALL_MODELS

import pasibot_pin as pp
from pasibot_pin.model.description import CUT_JOINTS, loop_table, render_urdf
from pasibot_pin.model.robot import planar_root_joint


@pytest.mark.parametrize("variant, legs", ALL_MODELS)
def test_committed_urdf_matches_its_xacro_source(variant, legs):
    committed = pp.urdf_path(variant, legs).read_text()
    assert render_urdf(variant, legs) == committed, "re-render with `make urdf` and commit"


@pytest.mark.parametrize("variant, legs", ALL_MODELS)
def test_urdf_is_a_strict_tree_with_named_cut_frames(variant, legs):
    root = ET.parse(pp.urdf_path(variant, legs)).getroot()
    links = {link.get("name") for link in root.findall("link")}
    children = [joint.find("child").get("link") for joint in root.findall("joint")]
    assert len(children) == len(set(children)), "a link with two parent joints"
    assert len(links) - len(children) == 1, "exactly one root link"
    assert links - set(children) == {"hip"}
    for loop in loop_table(variant, legs):
        assert loop.frame_a in links and loop.frame_b in links
    assert len(loop_table(variant, legs)) == legs * len(CUT_JOINTS[variant])


def test_yourdfpy_rejects_what_pinocchio_would_silently_accept(tmp_path):
    """Why the tree test matters: give a link a second parent joint."""
    text = pp.urdf_path("rigid", 1).read_text()
    extra = (
        '<joint name="bogus" type="revolute"><parent link="right_l3_rocker"/><child link="right_l2_coupler"/>'
        '<axis xyz="0 -1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>'
    )
    bad = tmp_path / "bad.urdf"
    bad.write_text(text.replace("</robot>", extra))
    import yourdfpy  # 1.7 s of imports (trimesh, networkx, scipy): only in the worker that runs these tests

    with pytest.raises(Exception):  # noqa: B017 - yourdfpy raises its own error types
        yourdfpy.URDF.load(str(bad), build_scene_graph=True, load_meshes=False)


@pytest.mark.parametrize("variant, legs", ALL_MODELS)
def test_yourdfpy_forward_kinematics_matches_pinocchio(variant, legs):
    path = pp.urdf_path(variant, legs)
    import yourdfpy

    urdf = yourdfpy.URDF.load(str(path), load_meshes=False)
    if legs == 2:
        model = pin.buildModelFromUrdf(str(path), planar_root_joint(), "hip_planar")
    else:
        model = pin.buildModelFromUrdf(str(path))
    data = model.createData()
    rng = np.random.default_rng(42)
    names = urdf.actuated_joint_names
    assert sorted(names) == sorted(n for n in model.names[1:] if n != "hip_planar")
    for _ in range(10):
        values = {n: rng.uniform(-np.pi, np.pi) if "slide" not in n else rng.uniform(-0.2, 0.2) for n in names}
        urdf.update_cfg(values)
        q = np.zeros(model.nq)  # the floating hip at the origin: world = hip frame
        for name, value in values.items():
            q[model.joints[model.getJointId(name)].idx_q] = value
        pin.framesForwardKinematics(model, data, q)
        for link in urdf.link_map:
            expected = urdf.get_transform(link)
            got = data.oMf[model.getFrameId(link, pin.FrameType.BODY)].homogeneous
            np.testing.assert_allclose(got, expected, atol=1e-12, err_msg=link)


@pytest.mark.parametrize("variant, legs", ALL_MODELS)
def test_urdf_masses_equal_the_masses_load_applies(robots, variant, legs):
    """The URDF's inertial tags and load()'s mass model give the same body inertias."""
    path = pp.urdf_path(variant, legs)
    model = pin.buildModelFromUrdf(str(path), planar_root_joint()) if legs == 2 else pin.buildModelFromUrdf(str(path))
    robot = robots[(variant, legs)]
    for j in range(1, model.njoints):
        np.testing.assert_allclose(
            model.inertias[j].toDynamicParameters(), robot.model.inertias[j].toDynamicParameters(), atol=1e-12
        )


def test_render_with_other_parameters_changes_lengths():
    text = render_urdf("rigid", 1, pp.Geometry(L=0.1, K=2.2))
    root = ET.fromstring(text)
    origins = {j.get("name"): j.find("origin").get("xyz") for j in root.findall("joint")}
    assert origins["right_j3"].split()[0] == repr(2.2 * 0.1)
    assert origins["right_j4"].split()[0] == repr(5.0 * 0.1)
