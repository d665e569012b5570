"""Shared fixtures: the source tree (SB_SOURCE_DIR, set by ctest) and small models."""

import os
import pathlib

import numpy as np
import pytest

import softbond

SOURCE_DIR = pathlib.Path(os.environ.get("SB_SOURCE_DIR", pathlib.Path(__file__).resolve().parents[2]))


@pytest.fixture
def source_dir():
    return SOURCE_DIR


@pytest.fixture
def sheet():
    """A 6 x 6 sheet, 1 m square, pinned at two corners."""
    return softbond.Model.sheet(nx=6, ny=6, bond_k=100, angle_k=0.01, mass=0.01, fixed=[0, 5])


def real_tolerance():
    """Relative rounding of the state's precision (float32 or float64)."""
    return 1e-5 if softbond.REAL_DTYPE == np.float32 else 1e-12
