"""Reference counts and memory over 10^5 create/destroy cycles (measured: resident set size)."""

import os
import sys

import numpy as np

import softbond


def resident_bytes():
    with open("/proc/self/statm") as statm:
        return int(statm.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def cycle(model, buffer_too):
    sphere = softbond.Collider("sphere", center=(0.5, 0.5, -0.2), radius=0.1, path=[(0, (0, 0, 0)), (1, (0, 0, 1))])
    handle = softbond.Handle([0], stiffness=10.0)
    solver = softbond.Solver(model, colliders=[sphere], handles=[handle], threads=1, on_break=print)
    solver.advance(1e-3)
    solver.load_state(solver.save_state())
    solver.get_positions(np.empty((model.vertex_count, 3)))
    solver.energies()
    solver.contact_force(sphere)
    if buffer_too:
        buffer = softbond.StateBuffer(solver)
        buffer.publish(solver)
        with buffer.acquire() as snapshot:
            snapshot.positions.sum()
    try:
        softbond.Model.from_arrays([[0, 0, 0], [1, 0, 0]], bonds=[[0, 0]], bond_k=1)
    except softbond.InvalidError:
        pass


def test_no_leak_over_100000_cycles():
    model = softbond.Model.sheet(nx=3, ny=3)
    for i in range(2000):
        cycle(model, i % 2 == 0)
    references = sys.getrefcount(model)
    before = resident_bytes()
    for i in range(100_000):
        cycle(model, i % 2 == 0)
    grown = resident_bytes() - before
    assert sys.getrefcount(model) == references
    # 10^5 cycles: a leak of even 20 bytes per cycle would show as 2 MB
    assert grown < 2_000_000, f"resident set grew by {grown} bytes"


def test_a_cycle_through_a_callback_is_collected():
    import gc

    freed = []

    class Marker:
        def __del__(self):
            freed.append(True)

    def make():
        marker, holder = Marker(), {}

        def force(vertex, time, position, velocity):
            return (0.0, 0.0, 0.0) if holder and marker else None

        holder["solver"] = softbond.Solver(softbond.Model.sheet(nx=3, ny=3), external_force=force, threads=1)
        holder["solver"].advance(1e-3)

    make()
    gc.collect()
    assert freed == [True]
