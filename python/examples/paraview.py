"""A model built from NumPy arrays and written out for ParaView: a block of tetrahedra (six per
cube of a 4 x 4 x 8 grid) of co-rotated FEM tissue by Young's modulus, its bottom fixed, bent by
gravity sideways; each frame is a VTK unstructured grid (.vtu, ASCII) and frames.pvd lists
them with their times (open frames.pvd in ParaView)."""

import argparse
import pathlib

import numpy as np

import softbond


def block(nx, ny, nz, h):
    """Grid vertices and the six tetrahedra of each cube (Kuhn's split, conforming)."""
    ijk = np.stack(np.meshgrid(np.arange(nx + 1), np.arange(ny + 1), np.arange(nz + 1), indexing="ij"), -1)
    vertices = ijk.reshape(-1, 3) * h
    index = np.arange(len(vertices)).reshape(nx + 1, ny + 1, nz + 1)
    paths = [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]
    tets = []
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                for path in paths:
                    corner = np.array([i, j, k])
                    chain = [index[tuple(corner)]]
                    for axis in path:
                        corner = corner.copy()
                        corner[axis] += 1
                        chain.append(index[tuple(corner)])
                    tets.append(chain)
    return vertices, np.array(tets)


def write_vtu(path, positions, tets, velocities):
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">',
             "<UnstructuredGrid>",
             f'<Piece NumberOfPoints="{len(positions)}" NumberOfCells="{len(tets)}">',
             '<PointData Vectors="velocity">',
             '<DataArray type="Float64" Name="velocity" NumberOfComponents="3" format="ascii">',
             " ".join(f"{v:.9g}" for v in velocities.ravel()),
             "</DataArray>", "</PointData>", "<Points>",
             '<DataArray type="Float64" NumberOfComponents="3" format="ascii">',
             " ".join(f"{x:.9g}" for x in positions.ravel()),
             "</DataArray>", "</Points>", "<Cells>",
             '<DataArray type="Int64" Name="connectivity" format="ascii">',
             " ".join(str(v) for v in tets.ravel()),
             "</DataArray>", '<DataArray type="Int64" Name="offsets" format="ascii">',
             " ".join(str(4 * (c + 1)) for c in range(len(tets))),
             "</DataArray>", '<DataArray type="UInt8" Name="types" format="ascii">',
             " ".join("10" for _ in range(len(tets))),  # VTK_TETRA
             "</DataArray>", "</Cells>", "</Piece>", "</UnstructuredGrid>", "</VTKFile>"]
    path.write_text("\n".join(lines) + "\n")


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--output", default="paraview_frames")
    parser.add_argument("--frames", type=int, default=20)
    args = parser.parse_args()
    out = pathlib.Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    vertices, tets = block(4, 4, 8, 0.01)  # 4 x 4 x 8 cm
    bottom = np.nonzero(vertices[:, 2] == 0)[0]
    model = softbond.Model.from_arrays(vertices, masses=1e-4, fixed=bottom, tetrahedra=tets, young_modulus=2e4,
                                       poisson_ratio=0.3)
    solver = softbond.Solver(model, integrator="implicit_euler", gravity=(9.81, 0, 0), drag=10.0)
    entries = []
    for frame in range(args.frames + 1):
        if frame:
            solver.advance(1e-3, steps=10)
        name = f"frame_{frame:04d}.vtu"
        write_vtu(out / name, solver.positions, tets, solver.velocities)
        entries.append(f'<DataSet timestep="{solver.time:.6g}" file="{name}"/>')
    (out / "frames.pvd").write_text('<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
                                    "<Collection>\n" + "\n".join(entries) + "\n</Collection>\n</VTKFile>\n")
    tip = solver.positions[np.argmax(vertices[:, 2])]
    print(f"{model.vertex_count} vertices, {model.tet_count} tetrahedra; the top bent {tip[0] * 1000:.2f} mm "
          f"along x; wrote {len(entries)} frames and {out / 'frames.pvd'}")


if __name__ == "__main__":
    main()
