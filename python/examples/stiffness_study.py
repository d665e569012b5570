"""A parameter study: the same cloth with five bond stiffnesses, its total energy against time
plotted into a PNG with matplotlib (drag makes it decay; stiffer bonds ring faster)."""

import argparse

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import softbond  # noqa: E402


def run(bond_k, steps, dt):
    cloth = softbond.Model.sheet(nx=15, ny=15, width=0.5, height=0.5, bond_k=bond_k, angle_k=0.001, mass=0.002,
                                 fixed=[210, 224])
    solver = softbond.Solver(cloth, integrator="velocity_verlet", drag=2.0)
    times, energy = np.empty(steps // 10), np.empty(steps // 10)
    for k in range(steps // 10):
        solver.advance(dt, steps=10)
        times[k] = solver.time
        e = solver.energies()
        energy[k] = e["kinetic"] + e["internal"]
    return times, energy


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--output", default="stiffness_study.png")
    parser.add_argument("--steps", type=int, default=2000)
    args = parser.parse_args()
    figure, axes = plt.subplots(figsize=(7, 4))
    for bond_k in (25, 50, 100, 200, 400):
        times, energy = run(bond_k, args.steps, 1e-3)
        axes.plot(times, energy, label=f"bond k = {bond_k} N/m")
        print(f"bond_k {bond_k:4d} N/m: peak kinetic + internal energy {energy.max():.4f} J")
    axes.set_xlabel("time (s)")
    axes.set_ylabel("kinetic + internal energy (J)")
    axes.set_title("A pinned cloth falling: energy against time")
    axes.legend()
    figure.tight_layout()
    figure.savefig(args.output, dpi=100)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
