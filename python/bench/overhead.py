"""The Python package's overhead (bench/results/python_overhead.md): the per-call cost of
advance() and of reading the state, on a one-vertex model, the default scene and the 100k sheet,
and the steps per second of a Python loop of advance(dt) against advance(dt, steps=n), whose loop
over sb_solver_advance runs in C (the C program's own loop: one library call per step).
Rounds are interleaved and the median is reported, so that a busy machine hurts both alike.

    PYTHONPATH=build/python /usr/bin/python3 python/bench/overhead.py [--rounds 5]
"""

import argparse
import pathlib
import statistics
import time

import numpy as np

import softbond

SCENES = pathlib.Path(__file__).resolve().parents[2] / "scenes"


def per_call(function, calls):
    start = time.perf_counter()
    for _ in range(calls):
        function()
    return (time.perf_counter() - start) / calls


def sheet_100k():
    n = 316  # 99 856 vertices, the benchmarks' sheet_100k
    h = 1.0 / (n - 1)
    model = softbond.Model.sheet(nx=n, ny=n, width=1.0, height=1.0, bond_k=100.0, angle_k=0.5 * 100 * h * h,
                                 stretch_bend_k=0.1 * 100 * h, density=0.1)
    return model, 2e-5


def loop_vs_c(solver, dt, steps, rounds):
    """Median seconds per step: a Python loop of advance(dt), and advance(dt, steps)."""
    python, c = [], []
    for _ in range(rounds):
        start = time.perf_counter()
        for _ in range(steps):
            solver.advance(dt)
        python.append((time.perf_counter() - start) / steps)
        start = time.perf_counter()
        solver.advance(dt, steps=steps)
        c.append((time.perf_counter() - start) / steps)
    return statistics.median(python), statistics.median(c)


def reads(solver, calls):
    out = np.empty((solver.vertex_count, 3))
    buffer = softbond.StateBuffer(solver)
    buffer.publish(solver)

    def view():
        with buffer.acquire() as snapshot:
            snapshot.positions

    return {"positions (new array)": per_call(lambda: solver.positions, calls),
            "get_positions(out)": per_call(lambda: solver.get_positions(out), calls),
            "snapshot view (acquire, view, release)": per_call(view, calls)}


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--rounds", type=int, default=5)
    args = parser.parse_args()
    print(f"softbond.REAL_DTYPE {softbond.REAL_DTYPE}")

    tiny = softbond.Solver(softbond.Model.from_arrays([[0, 0, 0]]), threads=1)
    python, c = loop_vs_c(tiny, 1e-6, 100_000, args.rounds)
    print(f"one vertex, 1 thread: advance(dt) {python * 1e6:.3f} us per call, "
          f"advance(dt, steps=n) {c * 1e6:.3f} us per step; overhead per call {(python - c) * 1e6:.3f} us")

    scene = softbond.Scene.load(SCENES / "default.yaml")
    solver = softbond.Solver(scene)
    python, c = loop_vs_c(solver, scene.dt, 2000, args.rounds)
    print(f"default scene ({scene.model.vertex_count} vertices): advance(dt) {python * 1e6:.2f} us per step, "
          f"advance(dt, steps=n) {c * 1e6:.2f} us; Python loop at {100 * c / python:.1f} % of the C loop")
    for name, seconds in reads(solver, 20_000).items():
        print(f"default scene: {name} {seconds * 1e6:.2f} us")

    model, dt = sheet_100k()
    solver = softbond.Solver(model)
    python, c = loop_vs_c(solver, dt, 40, args.rounds)
    print(f"sheet_100k ({model.vertex_count} vertices): advance(dt) {1 / python:.1f} steps/s, "
          f"advance(dt, steps=n) {1 / c:.1f} steps/s; Python loop at {100 * c / python:.1f} % of the C loop")
    for name, seconds in reads(solver, 200).items():
        print(f"sheet_100k: {name} {seconds * 1e6:.1f} us")

    calls = []
    callback = softbond.Solver(softbond.Model.from_arrays(np.zeros((1000, 3))), threads=1,
                               external_force=lambda vertex, t, x, v: calls.append(vertex))
    plain = softbond.Solver(softbond.Model.from_arrays(np.zeros((1000, 3))), threads=1)
    with_callback, without = loop_vs_c(callback, 1e-4, 20, args.rounds), loop_vs_c(plain, 1e-4, 20, args.rounds)
    per_vertex = (with_callback[1] - without[1]) / 1000
    print(f"external_force callback: {per_vertex * 1e6:.3f} us per call (1000 free vertices, {len(calls)} calls)")


if __name__ == "__main__":
    main()
