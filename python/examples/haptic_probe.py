"""The haptic probe driven from Python: the scene haptics_probe.yaml (a sheet held along two
sides, a 1 cm sphere above it), with the probe's pose set every step from a Python "device"
(here a scripted one: down 15 mm over 2 s, held, back up) and the force the sheet puts on it read
back after every step, as a device loop would render it. A second thread plays a display: it reads
the latest snapshot while the solver advances (the GIL is released during advance)."""

import argparse
import pathlib
import threading

import numpy as np

import softbond

HERE = pathlib.Path(__file__).resolve()
# the source tree's scenes, or the installed ones (share/softbond/scenes beside share/doc/softbond)
SCENES = next((p for p in (HERE.parents[2] / "scenes", HERE.parents[3] / "softbond" / "scenes") if p.is_dir()),
              HERE.parent)


def device_position(t, start):
    """The scripted device: 15 mm down over 2 s, held 1 s, up again over 2 s."""
    depth = 0.015 * (min(t, 2.0) / 2.0 if t < 3.0 else max(0.0, 1.0 - (t - 3.0) / 2.0))
    return start + np.array([0.0, 0.0, -depth])


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--scene", default=str(SCENES / "haptics_probe.yaml"))
    parser.add_argument("--duration", type=float, default=5.0, help="simulated seconds")
    args = parser.parse_args()
    scene = softbond.Scene.load(args.scene)
    probe = next(collider for collider in scene.colliders if collider.name == "probe")  # the scene's own
    solver = softbond.Solver(scene)
    buffer = softbond.StateBuffer(solver)
    start = probe.position.copy()

    done = threading.Event()
    lowest_seen = []

    def display():  # another thread: the latest state, without stopping the simulation
        while not done.is_set():
            with buffer.acquire() or _nothing() as snapshot:
                if snapshot is not None:
                    lowest_seen.append(float(snapshot.positions[:, 2].min()))
            done.wait(0.01)

    viewer = threading.Thread(target=display)
    viewer.start()
    dt, peak = scene.dt, 0.0
    try:
        for step in range(int(round(args.duration / dt))):
            target = device_position((step + 1) * dt, start)
            probe.set_pose(target - start)  # the pose at the end of this step
            solver.advance(dt, publish=buffer)
            force = solver.contact_force(probe)  # what the sheet pushes the probe with, N
            peak = max(peak, float(np.linalg.norm(force)))
            if step % int(round(0.5 / dt)) == 0:
                print(f"t = {solver.time:4.2f} s  probe z = {target[2] * 1000:6.2f} mm  "
                      f"force z = {force[2]:7.4f} N")
    finally:
        done.set()
        viewer.join()
    print(f"peak force {peak:.4f} N; the display thread read {len(lowest_seen)} snapshots, "
          f"the sheet's lowest point {min(lowest_seen) * 1000:.2f} mm")


class _nothing:
    """A with-block stand-in before the first snapshot."""

    def __enter__(self):
        return None

    def __exit__(self, *exc):
        return False


if __name__ == "__main__":
    main()
