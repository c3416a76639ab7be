"""The kinematic tree of any geometry without rendering the xacro each time (for design sweeps).

Rendering the xacro costs about 70 ms, most of a design's evaluation in a sweep. But every joint
and frame origin in ``urdf/pasibot.urdf.xacro`` is a linear combination of a few lengths (L, the
link lengths L0 .. L13, the sole's toe and heel, the hip half-width), and every orientation is a
constant. So the tree of any geometry is the seed's tree with its translations replaced by

    t(x) = t(x0) + A (x - x0),     x = :func:`length_vector` (geometry),

where A is *measured on the xacro itself*: one rendering per length, each length changed in
turn by 5 % (:func:`placement_map`, once per variant and leg count, kept on disk between processes).
The xacro stays the only source; this module never writes a number of its own. A map just measured
is checked on a rendering at an unrelated geometry, and refused (RuntimeError) if any translation
differs by more than :data:`CHECK_TOL` relative to L; a map read back from the disk is the one checked
when it was measured (its file is named by a hash of everything the rendering depends on, and holds
a digest of its arrays). ``tests/test_design_metrics.py`` checks the map on random geometries against
:func:`pasibot_pin.model.robot.load`. A new process builds a robot from the cache with no rendering at all
(``benchmarks/bench_start.py``: the three variants' robots in 0.08 s of CPU, 0.54 s when every process checked its
maps on a rendering).

Inertias are not part of the map: :func:`pasibot_pin.model.robot.apply_masses` sets them all.
"""

from __future__ import annotations

import functools
import hashlib
import importlib.util
import os
import zipfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

from pasibot_pin.model.description import build_tree, render_urdf
from pasibot_pin.model.params import Geometry, percentage_mass_model
from pasibot_pin.model.paths import XACRO_PATH, urdf_path
from pasibot_pin.model.variants import get_variant

STEP: float = 0.05
"""Relative change of each length when the map is measured (the map is exact: any step works
while the geometry stays valid)."""

CHECK_TOL: float = 1e-12
"""Largest translation error of the map at the check geometry, relative to L [-]."""


def length_vector(geometry: Geometry, variant: str) -> np.ndarray:
    """The lengths the tree's translations are linear in, for ``geometry`` [m].

    In order: L, l0 .. l13, foot_toe, foot_heel, hip_half_width.
    """
    toe, heel = geometry.foot_extent(variant)
    return np.array(
        [geometry.L, *(geometry.length(i) for i in range(14)), toe, heel, geometry.hip_half_width], dtype=float
    )


def _geometry_of(x: np.ndarray, variant: str) -> Geometry:
    """A geometry whose :func:`length_vector` is ``x``."""
    L = float(x[0])
    ratios = {f"r{i}": float(x[1 + i]) / L for i in range(1, 14)}
    toe, heel = float(x[15]), float(x[16])
    toe_field, heel_field = get_variant(variant).foot_fields  # the record names its sole's fields
    sole = {toe_field: toe / L, heel_field: heel / L}
    return Geometry(L=L, K=float(x[1]) / L, ratios=ratios, hip_half_width=float(x[17]), **sole)


def _tree(variant: str, legs: int, geometry: Geometry) -> pin.Model:
    return build_tree(render_urdf(variant, legs, geometry, percentage_mass_model(geometry, variant)), legs)


def _translations(model: pin.Model) -> np.ndarray:
    joints = [model.jointPlacements[j].translation for j in range(model.njoints)]
    frames = [f.placement.translation for f in model.frames]
    return np.array(joints + frames)


@dataclass(frozen=True)
class PlacementMap:
    """The seed's tree and the linear map from lengths to its translations.

    Attributes:
        model: the seed geometry's tree (inertias as rendered; :func:`tree` resets them).
        x0: its :func:`length_vector` [m].
        t0: its translations, joints then frames (n, 3) [m].
        A: d t / d x (n, 3, len(x0)) [-].

    """

    model: pin.Model
    x0: np.ndarray
    t0: np.ndarray
    A: np.ndarray

    def translations(self, x: np.ndarray) -> np.ndarray:
        """Every joint and frame translation (n, 3) [m] for the lengths ``x``."""
        return self.t0 + self.A @ (np.asarray(x, dtype=float) - self.x0)


def _cache_file(variant: str, legs: int) -> Path | None:
    """Where the map of ``variant``/``legs`` is kept between processes, or ``None`` (no cache folder).

    The name carries a hash of everything the map depends on: the xacro sources, this module,
    the xacro processor's own source, the seed geometry and the Pinocchio version. ``PASIBOT_CACHE``
    (or ``XDG_CACHE_HOME``) moves the folder; ``PASIBOT_CACHE=off`` turns the cache off.
    """
    root = os.environ.get("PASIBOT_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "pasibot_pin"
    )
    if root == "off":
        return None
    digest = hashlib.sha256()
    for source in sorted(XACRO_PATH.parent.glob("*.xacro")) + [Path(__file__)]:
        digest.update(source.read_bytes())
    xacro = importlib.util.find_spec("xacro")  # its source, not its version: importlib.metadata costs 40 ms a process
    if xacro is not None and xacro.origin is not None:
        digest.update(Path(xacro.origin).read_bytes())
    digest.update(f"{Geometry()!r}{pin.__version__}{STEP}".encode())
    return Path(root) / f"placements_{variant}_{legs}_{digest.hexdigest()[:16]}.npz"


def _measure(variant: str, legs: int, model: pin.Model) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(x0, t0, A) measured on the xacro: one rendering per length, plus a check at another geometry."""
    x0 = length_vector(Geometry(), variant)
    t0 = _translations(model)
    columns = []
    for k in range(len(x0)):
        x = x0.copy()
        x[k] *= 1.0 + STEP
        columns.append((_translations(_tree(variant, legs, _geometry_of(x, variant))) - t0) / (x[k] - x0[k]))
    return x0, t0, np.stack(columns, axis=-1)


def _arrays_digest(x0: np.ndarray, t0: np.ndarray, a: np.ndarray) -> str:
    """SHA-256 of a map's arrays (their shapes, types and bytes): what its cache file holds beside them."""
    digest = hashlib.sha256()
    for array in (x0, t0, a):
        digest.update(f"{array.shape}{array.dtype.str}".encode())
        digest.update(np.ascontiguousarray(array).tobytes())
    return digest.hexdigest()


def _read_cache(cache: Path | None) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """The arrays (x0, t0, A) kept in ``cache``, or ``None``: no file, or one that is not whole (its digest)."""
    if cache is None or not cache.is_file():
        return None
    try:
        with np.load(cache) as saved:
            arrays = saved["x0"], saved["t0"], saved["A"]
            digest = str(saved["digest"])
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile):  # not a whole archive of ours
        return None
    return arrays if digest == _arrays_digest(*arrays) else None


def _write_cache(cache: Path | None, out: PlacementMap) -> None:
    """Keep ``out``'s arrays in ``cache`` (written under a temporary name, then renamed; a read-only home: not kept)."""
    if cache is None:
        return
    try:
        cache.parent.mkdir(parents=True, exist_ok=True)
        tmp = cache.with_name(f".{cache.name}.{os.getpid()}.tmp.npz")
        np.savez(tmp, x0=out.x0, t0=out.t0, A=out.A, digest=_arrays_digest(out.x0, out.t0, out.A))
        os.replace(tmp, cache)
    except OSError:
        pass  # measured again next time


def check_map(out: PlacementMap, variant: str, legs: int) -> float:
    """The map's largest translation error [m] against a direct rendering at an unrelated geometry.

    The geometry changes every length at once (by up to 3 %).

    Raises:
        RuntimeError: the error passes :data:`CHECK_TOL` relative to L (the translations are not linear in the
            lengths: the xacro changed in a way this module does not support).

    """
    x = out.x0 * (1.0 + 0.03 * np.cos(np.arange(len(out.x0))))
    err = float(np.max(np.abs(_translations(_tree(variant, legs, _geometry_of(x, variant))) - out.translations(x))))
    if err > CHECK_TOL * x[0]:
        raise RuntimeError(f"the xacro's translations are not linear in the lengths (error {err:.3g} m)")
    return err


@functools.cache
def placement_map(variant: str, legs: int) -> PlacementMap:
    """The :class:`PlacementMap` of a variant and leg count, measured on the xacro.

    Kept in memory, and on disk between processes (:func:`_cache_file`, about 20 renderings of
    the xacro saved). The seed's tree is the committed default URDF (a test keeps it equal to
    its rendering). A map just measured is checked (:func:`check_map`, one more rendering) before
    it is kept; one read back is taken when its file is whole (the digest of its arrays) and its
    seed translations are the committed URDF's, else measured again.

    Raises:
        RuntimeError: the translations are not linear in the lengths (the xacro changed in a way
            this module does not support): the map disagrees with a direct rendering.

    """
    model = build_tree(urdf_path(variant, legs).read_text(), legs)
    cache = _cache_file(variant, legs)
    arrays = _read_cache(cache)
    if arrays is not None and np.array_equal(arrays[1], _translations(model)):
        return PlacementMap(model, *arrays)
    out = PlacementMap(model, *_measure(variant, legs, model))
    check_map(out, variant, legs)
    _write_cache(cache, out)
    return out


def tree(variant: str, legs: int, geometry: Geometry) -> pin.Model:
    """The kinematic tree of ``geometry`` (a copy of the seed's with its translations mapped)."""
    spec = get_variant(variant)
    pmap = placement_map(spec.name, legs)
    t = pmap.translations(length_vector(geometry, spec.name))
    model = pin.Model(pmap.model)
    for j in range(model.njoints):
        placement = model.jointPlacements[j]
        placement.translation = t[j]
        model.jointPlacements[j] = placement
    for i, frame in enumerate(model.frames):
        placement = frame.placement
        placement.translation = t[model.njoints + i]
        frame.placement = placement
        model.frames[i] = frame
    return model
