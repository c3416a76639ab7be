"""The 3-D walk page's camera follows the hip (issue 34): its parent frame is moved to the hip's (x, y) in every
animation frame, read back from the animation the page embeds."""

from __future__ import annotations

import numpy as np
import pytest

from pasibot_pin.model.design import Design, design_robot
from pasibot_pin.model.spatial import free_flyer_model, planar_to_spatial


def test_the_3d_pages_camera_follows_the_hip(monkeypatch):
    import meshcat

    from pasibot_pin.viz.walk3d import walk3d_html

    design = Design(variant="parallel", parallel_toe=6.0, parallel_heel=6.0, omega=2.0)
    robot = design_robot(design, 2, visuals=True)
    model = free_flyer_model(robot.model)
    q0 = planar_to_spatial(robot.q0)
    q = np.repeat(q0[None], 4, axis=0)
    q[:, 0] += np.array([0.0, 1.0, 2.0, 3.0])  # the hip walks 3 m forward ...
    q[:, 1] += np.array([0.0, 0.1, 0.2, 0.3])  # ... and drifts 0.3 m sideways
    seen = []
    monkeypatch.setattr(meshcat.Visualizer, "set_animation", lambda self, anim, **_: seen.append(anim))
    walk3d_html(robot, model, q, design.footprint(), 10.0, "test")
    (anim,) = seen
    clip = next(c for path, c in anim.clips.items() if path.lower().rstrip("/") == "/Cameras/default")
    positions = np.array(clip.tracks["position"].values, dtype=float)
    assert positions[:, 0] == pytest.approx(q[:, 0]) and positions[:, 1] == pytest.approx(q[:, 1])
    assert np.all(positions[:, 2] == 0.0)
