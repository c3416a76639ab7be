"""The placement map's disk cache (pasibot_pin.model.placements): a map read back is the one measured and checked,
and costs no rendering of the xacro; a damaged, foreign or stale file is measured again; a map that is not linear in
the lengths is refused and never kept.

The map's own values are checked elsewhere: against the xacro on random geometries (test_design_metrics.py's
fast-tree tests). Here the measurement is the session's map (the arrays a fresh measurement gives), handed out by a
stand-in for ``_measure`` that counts its calls, so that a test renders the xacro once (the check) and not twenty times.
"""

from __future__ import annotations

import numpy as np
import pytest

from pasibot_pin.model import placements

VARIANT, LEGS = "spring", 1


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """A cache folder of the test's own, a fresh in-memory cache, the measurements and renderings counted."""
    reference = placements.placement_map(VARIANT, LEGS)  # the session's map, as measured (or read) before
    monkeypatch.setenv("PASIBOT_CACHE", str(tmp_path))
    counts = {"measured": 0, "rendered": 0}
    real_render = placements.render_urdf

    def measure(variant, legs, model):
        counts["measured"] += 1
        return reference.x0.copy(), reference.t0.copy(), reference.A.copy()

    def render(*args, **kwargs):
        counts["rendered"] += 1
        return real_render(*args, **kwargs)

    monkeypatch.setattr(placements, "_measure", measure)
    monkeypatch.setattr(placements, "render_urdf", render)
    placements.placement_map.cache_clear()
    yield reference, counts, placements._cache_file(VARIANT, LEGS)
    placements.placement_map.cache_clear()  # later tests read the map from their own cache folder again


def _fresh():
    placements.placement_map.cache_clear()
    return placements.placement_map(VARIANT, LEGS)


def test_a_map_read_back_is_the_one_measured_and_renders_nothing(cache):
    reference, counts, path = cache
    first = _fresh()
    assert counts == {"measured": 1, "rendered": 1}  # measured, then checked on one rendering
    assert path.is_file() and path.parent == placements._cache_file(VARIANT, LEGS).parent
    again = _fresh()
    assert counts == {"measured": 1, "rendered": 1}  # read back: no measurement, no rendering
    for name in ("x0", "t0", "A"):
        assert np.array_equal(getattr(again, name), getattr(first, name))
        assert np.array_equal(getattr(again, name), getattr(reference, name))
    # and the map read back still is the xacro's: a direct rendering at another geometry
    assert placements.check_map(again, VARIANT, LEGS) <= placements.CHECK_TOL * again.x0[0]


@pytest.mark.parametrize("damage", ["a changed number", "no digest", "not an archive", "cut short", "another seed"])
def test_a_damaged_or_foreign_cache_file_is_measured_again(cache, damage):
    reference, counts, path = cache
    _fresh()
    with np.load(path) as saved:
        arrays = {name: saved[name].copy() for name in saved.files}
    if damage == "a changed number":
        arrays["A"][3, 1, 2] += 1e-9
        np.savez(path, **arrays)
    elif damage == "no digest":
        del arrays["digest"]
        np.savez(path, **arrays)
    elif damage == "not an archive":
        path.write_bytes(b"half a file")
    elif damage == "cut short":  # a file whose writer died half way (the cache is renamed whole, but a disk fills)
        path.write_bytes(path.read_bytes()[: path.stat().st_size // 2])
    else:  # whole and consistent, but of another seed tree: its t0 is not the committed URDF's
        arrays["t0"] = arrays["t0"] + 1e-3
        arrays["digest"] = np.array(placements._arrays_digest(arrays["x0"], arrays["t0"], arrays["A"]))
        np.savez(path, **arrays)
    out = _fresh()
    assert counts["measured"] == 2, damage
    assert np.array_equal(out.A, reference.A) and np.array_equal(out.t0, reference.t0)
    _fresh()  # the file was written whole again: read back with no measurement
    assert counts["measured"] == 2


def test_a_map_that_is_not_the_xacros_is_refused_and_not_kept(cache, monkeypatch):
    reference, counts, path = cache
    monkeypatch.setattr(placements, "_measure", lambda v, legs, m: (reference.x0, reference.t0, reference.A * 1.01))
    with pytest.raises(RuntimeError, match="not linear in the lengths"):
        _fresh()
    assert not path.exists()
