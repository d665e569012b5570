"""Colliders, handles, blades, scenes and every integrator through the package."""

import numpy as np
import pytest

import softbond


def test_sheet_rests_on_a_plane_and_the_plane_carries_its_weight():
    model = softbond.Model.sheet(nx=5, ny=5, width=0.4, height=0.4, bond_k=200, angle_k=0.01, mass=0.01)
    plane = softbond.Collider("plane", point=(0, 0, -0.1), normal=(0, 0, 1), name="floor")
    solver = softbond.Solver(model, colliders=[plane], drag=5.0, threads=1)
    solver.advance(1e-3, steps=2000)
    assert np.all(solver.positions[:, 2] > -0.1 - 1e-6)
    weight = model.masses.sum() * 9.81
    assert solver.contact_force(plane)[2] == pytest.approx(-weight, rel=0.05)
    assert solver.contact_force(0)[2] == solver.contact_force(plane)[2]
    assert plane.name == "floor"


def test_dynamic_sphere_is_caught_by_a_pinned_sheet():
    model = softbond.Model.sheet(nx=9, ny=9, width=1.0, height=1.0, bond_k=500, angle_k=0.01, mass=0.01,
                                 fixed=[0, 8, 72, 80])
    ball = softbond.Collider("sphere", center=(0.5, 0.5, 0.2), radius=0.1, mass=0.05)
    solver = softbond.Solver(model, colliders=[ball], drag=2.0, threads=1)
    solver.advance(1e-3, steps=1500)
    # it fell onto the sheet and stays on it, above the lowest vertex, holding it down
    assert 0.0 > ball.position[2] > solver.positions[:, 2].min()
    # over a second the sheet's impulse on it balances its weight (it bounces, but stays)
    impulse = 0.0
    for _ in range(1000):
        solver.advance(1e-3)
        impulse += solver.contact_force(ball)[2] * 1e-3
    assert impulse == pytest.approx(0.05 * 9.81 * 1.0, rel=0.1)
    assert 0.0 > ball.position[2] > solver.positions[:, 2].min()


def test_kinematic_collider_set_pose_moves_it():
    model = softbond.Model.sheet(nx=3, ny=3)
    box = softbond.Collider("box", center=(0, 0, 1), half_extents=(0.1, 0.1, 0.1))
    solver = softbond.Solver(model, colliders=[box], gravity=(0, 0, 0), threads=1)
    box.set_pose((0.5, 0, 0), (0, 0, 90))
    solver.advance(1e-2)
    np.testing.assert_allclose(box.position, [0.5, 0, 1], atol=1e-12)
    np.testing.assert_allclose(box.velocity, [50, 0, 0], rtol=1e-9)
    np.testing.assert_allclose(box.rotation, [[0, -1, 0], [1, 0, 0], [0, 0, 1]], atol=1e-12)


def test_hard_handle_follows_its_path():
    model = softbond.Model.sheet(nx=4, ny=4, bond_k=100)
    handle = softbond.Handle([0, 1], path=[(0.0, (0, 0, 0)), (0.1, (0, 0, 0.2))])
    solver = softbond.Solver(model, handles=[handle], gravity=(0, 0, 0), threads=1)
    solver.advance(1e-3, steps=100)
    positions = solver.positions
    np.testing.assert_allclose(positions[[0, 1]], model.rest_positions[[0, 1]] + [0, 0, 0.2], atol=1e-5)
    np.testing.assert_allclose(handle.targets, positions[[0, 1]], atol=1e-5)
    assert handle.held
    handle.release()
    assert not handle.held


def test_soft_handle_reports_its_force():
    model = softbond.Model.from_arrays([[0, 0, 0]], masses=1.0)
    handle = softbond.Handle([0], stiffness=100.0, damping=0.0)
    solver = softbond.Solver(model, handles=[handle], integrator="velocity_verlet", threads=1)
    solver.advance(1e-3, steps=1)
    assert handle.force[2] > 0  # it holds the vertex up against gravity


def test_blade_cuts_the_bonds_it_sweeps():
    model = softbond.Model.sheet(nx=6, ny=6, bond_k=100, fixed=list(range(6)))
    blade = softbond.Blade(a=(0.5, -0.5, -0.1), b=(0.5, -0.5, 0.1), path=[(0.0, (0, 0, 0)), (0.05, (0, 2, 0))])
    solver = softbond.Solver(model, blades=[blade], gravity=(0, 0, 0), threads=1)
    solver.advance(1e-3, steps=60)
    cut = solver.broken_bonds
    assert len(cut) > 0
    ends = model.bonds[cut]
    x = model.rest_positions[:, 0]
    # every cut bond crosses x = 0.5
    assert np.all((x[ends[:, 0]] - 0.5) * (x[ends[:, 1]] - 0.5) < 0)


@pytest.mark.parametrize("integrator", softbond.INTEGRATORS)
def test_every_integrator_runs_the_default_scene(source_dir, integrator):
    scene = softbond.Scene.load(source_dir / "scenes" / "default.yaml", {"integrator": integrator})
    assert scene.integrator == integrator
    solver = softbond.Solver(scene, threads=2, wait="yield")
    solver.advance(scene.dt, steps=50)
    assert solver.step_count == 50
    assert np.all(np.isfinite(solver.positions))


def test_a_scenes_own_colliders_and_handles(source_dir):
    scene = softbond.Scene.load(source_dir / "scenes" / "hook_pull.yaml")
    solver = softbond.Solver(scene, threads=1)
    assert len(solver.handles) == len(scene.handles) > 0
    assert [c.name for c in solver.colliders] == [c.name for c in scene.colliders]
    del scene  # the solver's views keep the scene alive
    solver.advance(1e-4, steps=5)
    assert solver.step_count == 5


def test_scene_from_dict_and_overrides():
    scene = softbond.Scene.from_dict(
        {"mesh": {"generator": "sheet", "nx": 4, "ny": 3}, "bond": {"k": 50}, "dt": 0.002},
        overrides={"gravity": [0, 0, -1]},
    )
    assert scene.model.vertex_count == 12
    assert scene.dt == 0.002
    assert scene.gravity == (0, 0, -1)
    assert scene.number("mesh.nx") == 4


def test_tissue_from_youngs_modulus():
    vertices = np.array([[0, 0, 0], [0.01, 0, 0], [0, 0.01, 0], [0, 0, 0.01]], dtype=float)
    tets = [[0, 1, 2, 3]]
    springs = softbond.Model.from_tets(vertices, tets, young_modulus=5e3, density=1000)
    assert springs.bond_count == 6 and springs.tet_count == 0
    volume = 0.01**3 / 6
    assert springs.masses.sum() == pytest.approx(1000 * volume)
    fem = softbond.Model.from_tets(vertices, tets, young_modulus=5e3, poisson_ratio=0.4, model="corotated", fixed=[0])
    assert fem.tet_count == 1 and fem.fixed[0]
    assert "corotated" in fem.terms


def test_reference_forces_of_a_stretched_bond():
    # Bond stretch 1/2 k (r - r0)^2: the force on each end is k (r - r0) along the bond.
    k, r0, r = 40.0, 1.0, 1.25
    model = softbond.Model.from_arrays([[0, 0, 0], [r0, 0, 0]], bonds=[[0, 1]], bond_k=k)
    forces, energies = model.reference_forces([[0, 0, 0], [r, 0, 0]])
    np.testing.assert_allclose(forces, [[k * (r - r0), 0, 0], [-k * (r - r0), 0, 0]], rtol=1e-12)
    assert energies["bond"] == pytest.approx(0.5 * k * (r - r0) ** 2, rel=1e-12)


def test_hinges_and_the_spring_factory_from_arrays():
    vertices = [[0, 0, 0], [1, 0, 0], [0.5, 1, 0], [0.5, -1, 0]]
    triangles = [[0, 1, 2], [1, 0, 3]]
    hinged = softbond.Model.from_arrays(vertices, triangles=triangles, hinges=[[0, 1, 2, 3]], bend_k=2.0)
    assert hinged.hinge_count == 1 and hinged.terms == ["bend"]
    folded = np.array(vertices, dtype=float)
    folded[2, 2] = 0.5  # fold one wing up: the hinge pushes back
    _, energies = hinged.reference_forces(folded)
    assert energies["bend"] > 0
    springs = softbond.Model.spring_mesh(vertices, triangles, stretch_k=50, bend_k=5, fixed=[0])
    # five edges and one bend spring between the two opposite vertices
    assert springs.bond_count == 6 and springs.terms == ["spring"] and springs.fixed[0]


def test_keyframes_as_dataclasses_and_the_state_dtype():
    model = softbond.Model.sheet(nx=3, ny=3)
    handle = softbond.Handle([4], path=[softbond.Keyframe(0.0), softbond.Keyframe(0.01, (0, 0, 0.1))])
    solver = softbond.Solver(model, handles=[handle], gravity=(0, 0, 0), threads=1)
    solver.advance(1e-3, steps=10)
    assert solver.positions[4, 2] == pytest.approx(0.1, abs=1e-6)
    assert softbond.REAL_DTYPE == (np.float64 if softbond.DOUBLE else np.float32)


def test_mesh_files_round_trip(tmp_path):
    model = softbond.Model.sheet(nx=4, ny=3)
    solver = softbond.Solver(model, threads=1)
    solver.advance(1e-3, steps=5)
    for name in ("state.obj", "state.ply"):
        softbond.export_mesh(tmp_path / name, solver.positions, solver.triangles)
        vertices, triangles = softbond.load_mesh(tmp_path / name)
        assert triangles.shape == (model.triangle_count, 3)
        # the exporter may renumber the vertices: compare them as sets (PLY stores float32)
        np.testing.assert_allclose(np.array(sorted(map(tuple, vertices))),
                                   np.array(sorted(map(tuple, solver.positions))), atol=1e-6)
    with pytest.raises(ValueError, match="'format'"):
        softbond.export_mesh(tmp_path / "state.stl", solver.positions, solver.triangles)
    with pytest.raises(softbond.FileError):
        softbond.load_mesh(tmp_path / "missing.obj")


def test_tearing_through_a_scene(source_dir):
    # Two handles pull a sheet whose bonds break beyond 1.25 r0: it tears (whether a vertex splits,
    # rather than the tear running along whole rows of bonds, depends on the precision).
    scene = softbond.Scene.load(source_dir / "scenes" / "tearing_sheet.yaml")
    broken = []
    solver = softbond.Solver(scene, on_break=lambda bond, i, j, time: broken.append(bond), threads=1)
    buffer = softbond.StateBuffer(solver)
    solver.advance(scene.dt, steps=5000, publish=buffer)
    n = scene.model.vertex_count
    assert len(broken) > 10 and sorted(broken) == list(solver.broken_bonds)
    assert n <= solver.vertex_count <= solver.vertex_capacity
    origins = solver.vertex_origins
    assert np.all(origins[n:] < n) and np.array_equal(origins[:n], np.arange(n))
    assert not solver.triangles_alive.all()
    assert solver.triangles.max() < solver.vertex_count
    with buffer.acquire() as snapshot:
        assert snapshot.vertex_count == solver.vertex_count
        assert snapshot.positions.shape == (solver.vertex_count, 3)


def test_adaptive_threads_can_be_turned_off(source_dir):
    scene = softbond.Scene.load(source_dir / "scenes" / "default.yaml")
    solver = softbond.Solver(scene, threads=2, adaptive_threads=False)
    solver.advance(scene.dt, steps=20)
    assert solver.step_count == 20
    with pytest.raises(TypeError):
        softbond.Solver(scene, adaptive_thread=False)  # a misspelt keyword is named, not ignored
