"""Dynamics on the constraint manifold.

Constrained inverse dynamics for every variant and motor layout (:mod:`.inverse`) and the
forward simulator (:mod:`.simulator`), both on the rows of
:class:`pasibot_pin.constraints.ConstraintSystem`.
"""
