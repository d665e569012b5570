"""Physics against closed forms: free fall, a spring's period, momentum."""

import math

import numpy as np
import pytest

import softbond
from conftest import real_tolerance


def test_free_fall_matches_closed_form():
    # Constant acceleration: velocity Verlet integrates it exactly, x = x0 + v0 t + g t^2 / 2.
    x0 = np.array([[0.0, 0.0, 10.0], [1.0, 2.0, 3.0]])
    v0 = np.array([[1.0, 0.0, 2.0], [0.0, -1.0, 0.0]])
    model = softbond.Model.from_arrays(x0, masses=0.5, velocities=v0)
    g = np.array([0.0, 0.0, -9.81])
    solver = softbond.Solver(model, integrator="velocity_verlet", gravity=g, threads=1)
    dt, steps = 1e-3, 500
    solver.advance(dt, steps=steps)
    t = dt * steps
    assert solver.time == pytest.approx(t, rel=1e-12)
    expected = x0 + v0 * t + 0.5 * g * t * t
    np.testing.assert_allclose(solver.positions, expected, rtol=50 * real_tolerance(), atol=1e-4)
    np.testing.assert_allclose(solver.velocities, v0 + g * t, rtol=50 * real_tolerance(), atol=1e-4)


@pytest.mark.parametrize("integrator", ["velocity_verlet", "symplectic_euler", "verlet"])
def test_spring_period_is_two_pi_sqrt_m_over_k(integrator):
    # One vertex of mass m on a bond of stiffness k to a pinned vertex: T = 2 pi sqrt(m / k).
    m, k, r0, amplitude = 0.2, 50.0, 1.0, 0.01
    model = softbond.Model.from_arrays(
        [[0, 0, 0], [0, 0, r0 + amplitude]], masses=[1.0, m], fixed=[0], bonds=[[0, 1]], bond_k=k, rest_lengths=r0
    )
    solver = softbond.Solver(model, integrator=integrator, gravity=(0, 0, 0), threads=1)
    period = 2 * math.pi * math.sqrt(m / k)
    dt = period / 2000
    z = []
    for _ in range(int(3.2 * period / dt)):
        solver.advance(dt)
        z.append(solver.positions[1, 2] - r0)
    z = np.array(z)
    # upward zero crossings, interpolated between steps
    up = np.nonzero((z[:-1] < 0) & (z[1:] >= 0))[0]
    times = (up + 1 + (-z[up]) / (z[up + 1] - z[up])) * dt
    assert len(times) >= 3
    measured = np.mean(np.diff(times))
    assert measured == pytest.approx(period, rel=2e-3)


def test_momentum_is_conserved_without_external_forces():
    model = softbond.Model.icosphere(subdivisions=2, radius=0.1, bond_k=200, angle_k=0.01, mass=0.01)
    rng = np.random.default_rng(7)
    v = rng.normal(0.0, 0.2, (model.vertex_count, 3))
    solver = softbond.Solver(model, integrator="velocity_verlet", gravity=(0, 0, 0), threads=2)
    solver.set_state(model.rest_positions, v)
    masses = model.masses[:, None]
    before = (masses * solver.velocities).sum(axis=0)
    solver.advance(1e-4, steps=2000)
    after = (masses * solver.velocities).sum(axis=0)
    scale = (masses * np.abs(v)).sum()
    assert np.all(np.abs(after - before) < 1e3 * real_tolerance() * scale)
    # ... and the body did deform: the internal energy is not zero
    assert solver.energies()["internal"] > 0
