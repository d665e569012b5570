"""Hello, softbond: a cloth pinned at two corners falls under gravity for one second."""

import softbond


def main():
    cloth = softbond.Model.sheet(nx=20, ny=20, width=1.0, height=1.0, bond_k=200, angle_k=0.01, mass=0.002,
                                 fixed=[380, 399])  # the two corners at y = 1
    solver = softbond.Solver(cloth, integrator="velocity_verlet", drag=1.0)
    solver.advance(1e-3, steps=1000)
    lowest = solver.positions[:, 2].min()
    energies = solver.energies()
    print(f"t = {solver.time:.3f} s after {solver.step_count} steps: the lowest point is at z = {lowest:.3f} m")
    print(f"energies: kinetic {energies['kinetic']:.4f} J, bonds {energies['bond']:.4f} J, "
          f"total {energies['total']:.4f} J")


if __name__ == "__main__":
    main()
