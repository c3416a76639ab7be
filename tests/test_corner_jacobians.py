"""model.spatial.CornerJacobians (the 3-D floor's corner rows, all corners at once) against Pinocchio's own
``getFrameJacobian`` (LOCAL_WORLD_ALIGNED) per corner, and the positions against ``oMf``: equal bit for bit at
random configurations, on every axis order the floor asks for."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from pasibot_pin.model.design import design_robot, load_design
from pasibot_pin.model.spatial import CornerJacobians, corner_frames, free_flyer_model, planar_to_spatial

COMB = "designs/3d/upright_fastest_comb0.6L_omega2.toml"


@pytest.mark.parametrize("axes", [(0, 1, 2), (2, 0, 1), (1,)])
def test_corner_rows_are_pinocchios_frame_jacobians(axes):
    design = load_design(COMB)
    robot = design_robot(design, 2, visuals=False)
    model = free_flyer_model(robot.model)
    q0 = planar_to_spatial(robot.q0)
    frames = corner_frames(model, q0, design.footprint())
    assert len(frames) >= 8
    rows = CornerJacobians(model, frames, axes)
    data, reference = model.createData(), model.createData()
    rng = np.random.default_rng(5)
    for _ in range(5):
        q = pin.integrate(model, q0, 0.3 * rng.standard_normal(model.nv))
        points, jac = rows(model, data, q)
        pin.computeJointJacobians(model, reference, q)
        pin.updateFramePlacements(model, reference)
        for k, frame in enumerate(frames):
            assert np.array_equal(points[k], reference.oMf[frame].translation)
            expected = pin.getFrameJacobian(model, reference, frame, pin.LOCAL_WORLD_ALIGNED)[list(axes)]
            assert np.array_equal(jac[k], expected), (frame, np.abs(jac[k] - expected).max())
