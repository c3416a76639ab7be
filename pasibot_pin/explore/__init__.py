"""Design exploration: sweeps and multi-objective optimisation of whole designs.

:mod:`~pasibot_pin.explore.plan` (which designs), :mod:`~pasibot_pin.explore.executors` (where
they run: a local process pool or a Dask cluster), :mod:`~pasibot_pin.explore.store` (a results
table that streams to disk and resumes), :mod:`~pasibot_pin.explore.sweep` and
:mod:`~pasibot_pin.explore.optimize` (the two studies). Each design's numbers come from
:func:`pasibot_pin.studies.design_metrics.design_metrics`.
"""
