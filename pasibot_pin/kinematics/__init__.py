"""Kinematics on the constraint manifold: the leg cycle and its metrics (:mod:`.leg`), biped walks (:mod:`.gait`)."""
