"""softbond: real-time soft-body simulation (mass-spring, molecular mechanics,
co-rotated FEM, nine integrators, contact, handles, cutting) from Python.

    import softbond
    model = softbond.Model.sheet(nx=10, ny=10, bond_k=100, fixed=[0, 9])
    solver = softbond.Solver(model, integrator="velocity_verlet")
    solver.advance(1e-3, steps=1000)
    print(solver.positions[-1], solver.energies()["total"])

The classes are the C library's objects (softbond._core, a CPython and NumPy
C extension): Model, Solver, Scene, Collider, Handle, StateBuffer, Snapshot;
Blade and Keyframe here are plain data. Library failures raise a subclass of
softbond.Error whose message is the library's one line. docs/python.md is the
manual.
"""

from dataclasses import dataclass
from typing import Optional, Sequence, Tuple

from ._core import (  # noqa: F401  (re-exported)
    DOUBLE,
    INTEGRATORS,
    REAL_DTYPE,
    TERMS,
    BusyError,
    Collider,
    DegenerateError,
    Error,
    FileError,
    Handle,
    InvalidError,
    Model,
    ParseError,
    Scene,
    Snapshot,
    Solver,
    StateBuffer,
    UnstableError,
    export_mesh,
    load_mesh,
)

Vector = Tuple[float, float, float]


@dataclass
class Keyframe:
    """A pose at a time: rotate (degrees about x, then y, then z) then translate (m).

    Anywhere a path is taken, a plain (time, translate, rotate) tuple does too."""

    time: float
    translate: Vector = (0.0, 0.0, 0.0)
    rotate: Vector = (0.0, 0.0, 0.0)

    def __iter__(self):
        return iter((self.time, self.translate, self.rotate))

    def __len__(self):
        return 3

    def __getitem__(self, index):
        return (self.time, self.translate, self.rotate)[index]


@dataclass
class Blade:
    """A cutting edge from a to b (m) that moves along a keyframed path; every bond it
    sweeps across is severed (Solver(blades=[...]))."""

    a: Vector
    b: Vector
    path: Optional[Sequence] = None
    interpolation: str = "linear"


__all__ = [
    "Blade", "BusyError", "Collider", "DOUBLE", "DegenerateError", "Error", "FileError", "Handle",
    "INTEGRATORS", "InvalidError", "Keyframe", "Model", "ParseError", "REAL_DTYPE", "Scene", "Snapshot",
    "Solver", "StateBuffer", "TERMS", "UnstableError", "export_mesh", "load_mesh",
]
