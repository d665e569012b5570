"""Python callables as the library's callbacks: external force, on-break, a program's own collider."""

import numpy as np
import pytest

import softbond


def test_external_force_is_called_per_free_vertex_with_its_state():
    calls = []

    def push(vertex, time, position, velocity):
        calls.append((vertex, time, position, velocity))
        return (0.0, 0.0, 2.0)  # N: lifts a 1 kg vertex against gravity

    model = softbond.Model.from_arrays([[0, 0, 0], [1, 0, 0], [2, 0, 0]], masses=[1, 1, 0], fixed=[2])
    solver = softbond.Solver(model, integrator="symplectic_euler", gravity=(0, 0, -2.0), external_force=push, threads=1)
    solver.advance(0.01, steps=3)
    # the free vertices only, in vertex order, with (x, y, z) tuples
    assert {c[0] for c in calls} == {0, 1}
    assert calls[0][0] == 0 and calls[1][0] == 1
    assert calls[1][2] == (1.0, 0.0, 0.0)
    assert all(len(c[3]) == 3 for c in calls)
    # the force cancels gravity: nothing moved
    np.testing.assert_array_equal(solver.positions, model.rest_positions)


def test_callback_exception_stops_the_run_and_is_raised():
    def broken(vertex, time, position, velocity):
        raise KeyError("from the callback")

    model = softbond.Model.from_arrays([[0, 0, 0]])
    solver = softbond.Solver(model, external_force=broken, threads=1)
    with pytest.raises(KeyError, match="from the callback"):
        solver.advance(0.01, steps=100)
    assert solver.step_count == 1


def test_on_break_reports_each_broken_bond():
    broken = []
    model = softbond.Model.from_arrays(
        [[0, 0, 0], [0, 0, -1], [0, 0, -2]],
        fixed=[0],
        masses=1.0,
        bonds=[[0, 1], [1, 2]],
        bond_k=100.0,
        break_max=[1.05, 100.0],
    )
    solver = softbond.Solver(
        model, integrator="velocity_verlet", gravity=(0, 0, -9.81), on_break=lambda *a: broken.append(a), threads=1
    )
    solver.advance(1e-3, steps=500)
    assert len(broken) == 1
    bond, i, j, time = broken[0]
    assert (bond, i, j) == (0, 0, 1)
    assert 0 < time < 0.5
    assert list(solver.broken_bonds) == [0]


def test_custom_collider_floor():
    # A program's own floor at z = 0: the dropped vertices come to rest on it.
    def floor(vertex, t0, t1, start, end, thickness):
        if end[2] >= 0.0:
            return None
        fraction = start[2] / (start[2] - end[2]) if start[2] > 0 else 0.0
        return {"fraction": min(max(fraction, 0.0), 1.0), "depth": 0.0, "normal": (0, 0, 1)}

    model = softbond.Model.from_arrays([[0, 0, 0.05], [1, 0, 0.1]], masses=1.0)
    collider = softbond.Collider.custom(floor, name="floor")
    # two threads: the solver's team calls collide from both, each call taking the GIL
    solver = softbond.Solver(model, integrator="velocity_verlet", colliders=[collider], threads=2)
    solver.advance(1e-3, steps=500)
    z = solver.positions[:, 2]
    assert np.all(np.abs(z) < 1e-3)
    force = solver.contact_force(collider)
    assert force[2] == pytest.approx(-2 * 9.81, rel=0.05)  # the floor carries both weights


def test_custom_collider_exception_is_raised():
    def broken(vertex, t0, t1, start, end, thickness):
        raise ZeroDivisionError("inside collide")

    model = softbond.Model.from_arrays([[0, 0, 0.05], [1, 0, 0.1]])
    solver = softbond.Solver(model, colliders=[softbond.Collider.custom(broken)], threads=2)
    with pytest.raises(ZeroDivisionError, match="inside collide"):
        solver.advance(1e-3, steps=50)
    assert solver.step_count == 1
