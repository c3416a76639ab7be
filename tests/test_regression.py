"""Nothing lost in the redesign: today's figures equal the ones recorded before it.

The golden figures (``tests/data/golden_figures.npz``) were computed by the code as it stood
before the constraint core was rewritten (see ``tests/golden_figures.py``). Torques, K_e,
reactions, configurations and path metrics must come out equal to 1e-9 relative; simulated
traces to their integration tolerance.
"""

from __future__ import annotations

import numpy as np
import pytest
from golden_figures import GOLDEN, GROUPS, compute

# Relative tolerance of a figure, by the group its key starts with; simulations integrate
# (RK4, a projection to 1e-12 per step), so their traces agree to the integration tolerance.
RTOL = {"sim": 1e-6}
DEFAULT_RTOL = 1e-9
ATOL = 1e-12
"""Absolute floor [SI]: a figure that is zero (the spring foot's pitch, held level) compares absolutely."""
ARGMAX = [5, 6, 8]
ARGMAX_ATOL = 1e-5
"""The crank angles of the stance-path peaks and of the largest lift (``metrics/*`` entries 5, 6
and 8) are argmaxes of smooth maxima f0 - c (theta - theta*)^2: a change e of the path moves them
by sqrt(e / c). The closure solves q to 1e-12 m, so with c ~ 0.1 m/rad^2 they are defined to
~3e-6 rad only; they compare to 1e-5 rad [rad]."""


@pytest.fixture(scope="module")
def golden():
    with np.load(GOLDEN) as data:
        return {k: data[k] for k in data.files}


@pytest.mark.parametrize("group", list(GROUPS))
def test_figures_unchanged(golden, group):
    figures = compute((group,))
    assert figures, group
    missing = sorted(k for k in figures if k not in golden)
    assert not missing, f"figures with no golden value: {missing[:5]}"
    for key, value in figures.items():
        ref = golden[key]
        assert value.shape == ref.shape, key
        rtol = RTOL.get(key.split("/", 1)[0], DEFAULT_RTOL)
        diff = np.abs(value - ref)
        if key.startswith("metrics/"):
            assert np.max(diff[ARGMAX]) <= ARGMAX_ATOL, f"{key}: argmax angles moved by {np.max(diff[ARGMAX]):.3e} rad"
            diff[ARGMAX] = 0.0
        scale = float(np.max(np.abs(ref))) if ref.size else 0.0
        err = float(np.max(diff)) if ref.size else 0.0
        assert err <= rtol * scale + ATOL, f"{key}: change {err:.3e} > {rtol:g} x {scale:.3e} + {ATOL:g}"


def test_every_golden_figure_is_recomputed(golden):
    """The golden file holds no figure that ``compute`` no longer produces (none silently dropped)."""
    keys = set()
    for group in GROUPS:
        keys |= {k for k in golden if k.split("/", 1)[0] in _prefixes(group)}
    assert keys == set(golden)


def _prefixes(group: str) -> set[str]:
    return {
        "torques": {"K_e", "torques"},
        "closure_and_paths": {"q0", "metrics", "cycle", "walk"},
        "contact_energy_motor": {"contact", "energy", "single_motor"},
        "simulations": {"sim"},
    }[group]
