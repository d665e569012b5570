"""Type hints for softbond._core, the C extension (see the docstrings there)."""

from os import PathLike
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

Vector = Union[Tuple[float, float, float], Sequence[float], npt.ArrayLike]
KeyframeLike = Union[Tuple[float, Vector], Tuple[float, Vector, Vector], Sequence[Any]]
Path = Union[str, bytes, PathLike]
Indices = npt.ArrayLike
PerElement = Union[float, npt.ArrayLike]

INTEGRATORS: Tuple[str, ...]
TERMS: Tuple[str, ...]
REAL_DTYPE: np.dtype
DOUBLE: int

class Error(Exception):
    status: str

class InvalidError(Error, ValueError): ...
class FileError(Error, OSError): ...
class ParseError(Error): ...
class DegenerateError(Error): ...
class UnstableError(Error): ...
class BusyError(Error): ...

class Model:
    @classmethod
    def from_arrays(
        cls,
        vertices: npt.ArrayLike,
        *,
        masses: Optional[PerElement] = ...,
        velocities: Optional[npt.ArrayLike] = ...,
        fixed: Optional[Indices] = ...,
        bonds: Optional[Indices] = ...,
        bond_k: Optional[PerElement] = ...,
        spring_k: Optional[PerElement] = ...,
        spring_damping: Optional[PerElement] = ...,
        rest_lengths: Optional[PerElement] = ...,
        break_min: Optional[PerElement] = ...,
        break_max: Optional[PerElement] = ...,
        triangles: Optional[Indices] = ...,
        angle_k: Optional[PerElement] = ...,
        stretch_bend_k: Optional[PerElement] = ...,
        tetrahedra: Optional[Indices] = ...,
        young_modulus: Optional[PerElement] = ...,
        poisson_ratio: Optional[PerElement] = ...,
        hinges: Optional[Indices] = ...,
        bend_k: Optional[PerElement] = ...,
    ) -> Model: ...
    @classmethod
    def from_mesh(
        cls,
        vertices: npt.ArrayLike,
        triangles: Indices,
        *,
        bond_k: float = ...,
        angle_k: float = ...,
        stretch_bend_k: float = ...,
        spring_k: float = ...,
        spring_damping: float = ...,
        bend_k: float = ...,
        mass: float = ...,
        density: float = ...,
        break_strain: float = ...,
        fixed: Optional[Indices] = ...,
    ) -> Model: ...
    @classmethod
    def spring_mesh(
        cls,
        vertices: npt.ArrayLike,
        triangles: Indices,
        *,
        stretch_k: float = ...,
        stretch_damping: float = ...,
        bend_k: float = ...,
        bend_damping: float = ...,
        vicinity: float = ...,
        vicinity_k: float = ...,
        vicinity_damping: float = ...,
        mass: float = ...,
        density: float = ...,
        break_strain: float = ...,
        fixed: Optional[Indices] = ...,
    ) -> Model: ...
    def reference_forces(
        self, positions: npt.ArrayLike, velocities: Optional[npt.ArrayLike] = ...
    ) -> Tuple[npt.NDArray[np.float64], Dict[str, float]]: ...
    @classmethod
    def sheet(
        cls,
        *,
        nx: int = ...,
        ny: int = ...,
        width: float = ...,
        height: float = ...,
        jitter: float = ...,
        seed: int = ...,
        **material: Any,
    ) -> Model: ...
    @classmethod
    def icosphere(cls, *, subdivisions: int = ..., radius: float = ..., **material: Any) -> Model: ...
    @classmethod
    def load(cls, path: Path, **material: Any) -> Model: ...
    @classmethod
    def from_tets(
        cls,
        vertices: npt.ArrayLike,
        tetrahedra: Indices,
        *,
        tissue: str = ...,
        young_modulus: float = ...,
        density: float = ...,
        damping: float = ...,
        poisson_ratio: float = ...,
        stiffness_damping: float = ...,
        model: str = ...,
        fixed: Optional[Indices] = ...,
    ) -> Model: ...
    vertex_count: int
    bond_count: int
    triangle_count: int
    tet_count: int
    hinge_count: int
    rest_positions: npt.NDArray[np.float64]
    initial_velocities: npt.NDArray[np.float64]
    masses: npt.NDArray[np.float64]
    fixed: npt.NDArray[np.bool_]
    triangles: npt.NDArray[np.uint32]
    bonds: npt.NDArray[np.uint32]
    rest_lengths: npt.NDArray[np.float64]
    terms: List[str]

class Collider:
    def __init__(
        self,
        shape: str,
        *,
        name: str = ...,
        point: Vector = ...,
        normal: Vector = ...,
        center: Vector = ...,
        radius: float = ...,
        a: Vector = ...,
        b: Vector = ...,
        half_extents: Vector = ...,
        rotate: Vector = ...,
        vertices: Optional[npt.ArrayLike] = ...,
        triangles: Optional[Indices] = ...,
        friction: float = ...,
        static_friction: float = ...,
        restitution: float = ...,
        thickness: float = ...,
        path: Optional[Sequence[KeyframeLike]] = ...,
        interpolation: str = ...,
        mass: float = ...,
        velocity: Vector = ...,
        angular_velocity: Vector = ...,
    ) -> None: ...
    @classmethod
    def custom(
        cls,
        collide: Callable[[int, float, float, Tuple[float, float, float], Tuple[float, float, float], float],
                          Optional[Mapping[str, Any]]],
        *,
        begin_step: Optional[Callable[[float, float], None]] = ...,
        name: str = ...,
        bounds: Optional[Tuple[Vector, Vector]] = ...,
    ) -> Collider: ...
    def set_pose(self, translate: Vector, rotate: Vector = ...) -> None: ...
    name: str
    position: npt.NDArray[np.float64]
    velocity: npt.NDArray[np.float64]
    rotation: npt.NDArray[np.float64]
    angular_velocity: npt.NDArray[np.float64]
    inner_radius: float

class Handle:
    def __init__(
        self,
        vertices: Indices,
        *,
        name: str = ...,
        stiffness: float = ...,
        damping: float = ...,
        center: Optional[Vector] = ...,
        path: Optional[Sequence[KeyframeLike]] = ...,
        interpolation: str = ...,
        release_time: Optional[float] = ...,
    ) -> None: ...
    def set_pose(self, translate: Vector, rotate: Vector = ...) -> None: ...
    def release(self) -> None: ...
    def grab(self, vertex: Optional[int] = ...) -> None: ...
    held: bool
    force: npt.NDArray[np.float64]
    targets: npt.NDArray[np.float64]
    name: str

class Scene:
    @classmethod
    def load(cls, path: Path, overrides: Optional[Union[Mapping[str, Any], Sequence[str]]] = ...) -> Scene: ...
    @classmethod
    def from_dict(
        cls,
        scene: Dict[str, Any],
        base_dir: Optional[Path] = ...,
        overrides: Optional[Union[Mapping[str, Any], Sequence[str]]] = ...,
    ) -> Scene: ...
    def number(self, key: str) -> float: ...
    model: Model
    dt: float
    duration: float
    frame_interval: float
    name: str
    integrator: str
    gravity: Tuple[float, float, float]
    colliders: Tuple[Collider, ...]
    handles: Tuple[Handle, ...]

class Snapshot:
    def release(self) -> None: ...
    def __enter__(self) -> Snapshot: ...
    def __exit__(self, *exc: Any) -> bool: ...
    positions: npt.NDArray[Any]
    velocities: npt.NDArray[Any]
    sequence: int
    step: int
    time: float
    vertex_count: int
    energies: Dict[str, float]

class StateBuffer:
    def __init__(self, solver: Solver, max_readers: int = ...) -> None: ...
    def acquire(self) -> Optional[Snapshot]: ...
    def publish(self, solver: Solver) -> None: ...
    published: int
    skipped: int

ExternalForce = Callable[[int, float, Tuple[float, float, float], Tuple[float, float, float]], Optional[Vector]]
OnBreak = Callable[[int, int, int, float], Any]

class Solver:
    def __init__(
        self,
        model: Union[Model, Scene],
        *,
        integrator: str = ...,
        gravity: Vector = ...,
        drag: float = ...,
        kernels: str = ...,
        threads: int = ...,
        pin_threads: bool = ...,
        wait: str = ...,
        adaptive_threads: bool = ...,
        colliders: Optional[Sequence[Collider]] = ...,
        contact_thickness: float = ...,
        self_collision: bool = ...,
        handles: Optional[Sequence[Handle]] = ...,
        blades: Optional[Sequence[Any]] = ...,
        external_force: Optional[ExternalForce] = ...,
        on_break: Optional[OnBreak] = ...,
        max_splits: int = ...,
        max_splits_per_step: int = ...,
        implicit_tolerance: float = ...,
        implicit_solver: str = ...,
        implicit_newton_iterations: int = ...,
        implicit_cg_iterations: int = ...,
        implicit_definite: bool = ...,
        pbd_iterations: int = ...,
        vbd_iterations: int = ...,
        vbd_chebyshev_rho: float = ...,
        vbd_relaxation: float = ...,
        adaptive: bool = ...,
        min_dt: float = ...,
        adaptive_tolerance: float = ...,
    ) -> None: ...
    def advance(self, dt: float, *, steps: int = ..., publish: Optional[StateBuffer] = ...) -> None: ...
    def get_positions(self, out: Optional[npt.NDArray[np.float64]] = ...) -> npt.NDArray[np.float64]: ...
    def get_velocities(self, out: Optional[npt.NDArray[np.float64]] = ...) -> npt.NDArray[np.float64]: ...
    def get_forces(self, out: Optional[npt.NDArray[np.float64]] = ...) -> npt.NDArray[np.float64]: ...
    def set_state(self, positions: npt.ArrayLike, velocities: Optional[npt.ArrayLike] = ...) -> None: ...
    def set_gravity(self, gravity: Vector) -> None: ...
    def energies(self) -> Dict[str, float]: ...
    def contact_force(self, collider: Union[Collider, int]) -> npt.NDArray[np.float64]: ...
    def save_state(self) -> bytes: ...
    def load_state(self, data: bytes) -> None: ...
    positions: npt.NDArray[np.float64]
    velocities: npt.NDArray[np.float64]
    forces: npt.NDArray[np.float64]
    time: float
    step_count: int
    vertex_count: int
    vertex_capacity: int
    vertex_origins: npt.NDArray[np.uint32]
    triangles: npt.NDArray[np.uint32]
    triangles_alive: npt.NDArray[np.bool_]
    broken_bonds: npt.NDArray[np.uint32]
    last_step: Dict[str, Any]
    model: Model
    colliders: Tuple[Collider, ...]
    handles: Tuple[Handle, ...]

def load_mesh(path: Path) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.uint32]]: ...
def export_mesh(
    path: Path, vertices: npt.ArrayLike, triangles: Indices, *, format: Optional[str] = ..., up: Vector = ...
) -> None: ...
