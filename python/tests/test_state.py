"""The state as NumPy arrays, checkpoints, snapshots from another thread."""

import threading

import numpy as np
import pytest

import softbond


def test_copies_track_the_state_and_fill_the_callers_array(sheet):
    solver = softbond.Solver(sheet, threads=1)
    first = solver.positions
    out = np.empty((solver.vertex_count, 3))
    assert solver.get_positions(out) is out
    np.testing.assert_array_equal(out, first)
    solver.advance(1e-3, steps=20)
    assert solver.get_positions(out) is out
    assert not np.array_equal(out, first)  # the free vertices fell
    np.testing.assert_array_equal(out, solver.positions)
    np.testing.assert_array_equal(out[[0, 5]], sheet.rest_positions[[0, 5]])  # the pinned ones did not
    forces = solver.get_forces(np.empty_like(out))
    velocities = solver.get_velocities(np.empty_like(out))
    assert forces.dtype == velocities.dtype == np.float64
    assert velocities[10, 2] < 0


def test_snapshot_views_are_read_only_and_equal_the_state(sheet):
    solver = softbond.Solver(sheet, threads=1)
    buffer = softbond.StateBuffer(solver)
    assert buffer.acquire() is None
    solver.advance(1e-3, steps=7, publish=buffer)
    with buffer.acquire() as snapshot:
        assert snapshot.step == 7 and snapshot.sequence == 7
        positions = snapshot.positions
        assert positions.dtype == softbond.REAL_DTYPE
        assert positions.shape == (sheet.vertex_count, 3)
        assert not positions.flags.writeable
        with pytest.raises(ValueError):
            positions[0, 0] = 1.0
        expected = solver.positions.astype(softbond.REAL_DTYPE)
        np.testing.assert_array_equal(positions, expected)
        assert snapshot.time == pytest.approx(7e-3)
    with pytest.raises(RuntimeError, match="released"):
        snapshot.velocities


def test_checkpoint_bytes_round_trip_bitwise(sheet):
    solver = softbond.Solver(sheet, integrator="velocity_verlet", threads=1)
    solver.advance(1e-3, steps=100)
    saved = solver.save_state()
    assert isinstance(saved, bytes)
    solver.advance(1e-3, steps=100)
    straight = solver.positions
    straight_bytes = solver.save_state()
    other = softbond.Solver(sheet, integrator="velocity_verlet", threads=2)
    other.load_state(saved)
    assert other.step_count == 100
    other.advance(1e-3, steps=100)
    np.testing.assert_array_equal(other.positions, straight)
    assert other.save_state() == straight_bytes


def test_checkpoint_of_another_model_is_refused(sheet):
    solver = softbond.Solver(sheet, threads=1)
    other = softbond.Solver(softbond.Model.sheet(nx=4, ny=4), threads=1)
    with pytest.raises(softbond.InvalidError) as error:
        other.load_state(solver.save_state())
    assert str(error.value)  # the library's line
    corrupt = bytearray(solver.save_state())
    corrupt[-1] ^= 0xFF
    with pytest.raises(softbond.Error):
        solver.load_state(bytes(corrupt))


def test_gil_is_released_while_advancing():
    # A reader thread must observe new snapshots while advance() runs in this thread:
    # with the GIL held for the whole advance it could not run at all meanwhile.
    model = softbond.Model.sheet(nx=40, ny=40, bond_k=100, fixed=[0, 39])
    solver = softbond.Solver(model, integrator="xpbd", threads=1)
    buffer = softbond.StateBuffer(solver, max_readers=1)
    running = threading.Event()
    stop = threading.Event()
    seen_while_running = set()

    def reader():
        while not stop.is_set():
            snapshot = buffer.acquire()
            if snapshot is not None:
                if running.is_set():
                    seen_while_running.add(snapshot.sequence)
                    float(snapshot.positions[-1, 2])  # read it
                snapshot.release()

    thread = threading.Thread(target=reader)
    thread.start()
    try:
        running.set()
        solver.advance(1e-3, steps=400, publish=buffer)
        running.clear()
    finally:
        stop.set()
        thread.join()
    assert buffer.published == 400 - buffer.skipped
    # progress during the advance: several distinct snapshots seen, not only the last one
    assert len(seen_while_running) >= 3, seen_while_running
    assert min(seen_while_running) < 400


def test_other_calls_are_refused_while_advancing():
    model = softbond.Model.sheet(nx=30, ny=30)
    solver = softbond.Solver(model, integrator="xpbd", threads=1)
    refused = []
    started = threading.Event()

    def advance():
        started.set()
        solver.advance(1e-3, steps=300)

    thread = threading.Thread(target=advance)
    thread.start()
    started.wait()
    while thread.is_alive():
        try:
            solver.positions
        except RuntimeError as error:
            refused.append(str(error))
    thread.join()
    assert solver.step_count == 300
    assert refused and "advancing" in refused[0]
