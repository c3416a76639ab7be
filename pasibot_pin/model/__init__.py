"""The model layer: parameters, variant records, the URDF description, masses, ``load()`` and the closure.

:mod:`.closure` assembles closed configurations (``q0`` of ``load()``) on the rows of
:class:`pasibot_pin.constraints.ConstraintSystem`; nothing here integrates or fits.
"""
