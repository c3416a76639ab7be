"""Shared fixtures: robots are loaded once per session (loading is cheap but not free)."""

from __future__ import annotations

import os

import matplotlib
import pytest

matplotlib.use("Agg")
os.environ.setdefault("MPLBACKEND", "Agg")

import pasibot_pin as pp  # noqa: E402

ALL_MODELS = [(variant, legs) for variant in pp.VARIANTS for legs in (1, 2)]


@pytest.fixture(scope="session")
def robots():
    """Dict (variant, legs) -> loaded robot with default parameters."""
    return {key: pp.load(*key) for key in ALL_MODELS}


@pytest.fixture(scope="session")
def L():
    """The default crank length [m]."""
    return pp.Geometry().L
