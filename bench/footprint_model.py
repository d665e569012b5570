#!/usr/bin/env python3
"""How evenly a spring net answers a load spread over the surface by a
footprint (kernels/contact/footprint.c), in a linear model: the default
sheet's mesh (21 x 21 vertices, diagonals alternating, held along its four
sides) as a membrane under uniform tension, its out-of-plane stiffness
K = the graph Laplacian with weight 1 on the edges along the axes and 1/2
on the diagonals (tension / length, spacing 1). A load spread over the
vertices by weights s (summing to 1) that holds their mean Σ s_i u_i at a
depth meets the stiffness 1 / (sᵀ K⁻¹ s). The probe slides along the middle
row; printed: the stiffness over each of two vertices (one where eight
edges meet, one where four do) against its mean halfway to the neighbouring
vertices, minus 1, for a triangle's barycentric weights and for footprints
of 1 to 2.5 spacings (the cubic spline kernel of the rest distance).

    python3 bench/footprint_model.py
"""
import numpy as np

N = 21


def index(row, col):
    return row * N + col


def laplacian():
    K = np.zeros((N * N, N * N))
    edges = []
    for r in range(N):
        for c in range(N):
            if c + 1 < N:
                edges.append((index(r, c), index(r, c + 1), 1.0))
            if r + 1 < N:
                edges.append((index(r, c), index(r + 1, c), 1.0))
    for r in range(N - 1):
        for c in range(N - 1):
            if (r + c) % 2 == 0:
                edges.append((index(r, c), index(r + 1, c + 1), 0.5))
            else:
                edges.append((index(r, c + 1), index(r + 1, c), 0.5))
    for i, j, w in edges:
        K[i, i] += w
        K[j, j] += w
        K[i, j] -= w
        K[j, i] -= w
    return K


def compliance(K):
    free = [index(r, c) for r in range(1, N - 1) for c in range(1, N - 1)]
    C = np.zeros_like(K)
    C[np.ix_(free, free)] = np.linalg.inv(K[np.ix_(free, free)])
    return C


def barycentric(x):
    """The weights of the point x (in spacings) along row 10."""
    w = np.zeros(N * N)
    c = int(np.floor(x))
    f = x - c
    w[index(10, c)] += 1 - f
    if f > 0:
        w[index(10, c + 1)] += f
    return w


def kernel(q):
    q = np.clip(q, 0.0, 1.0)
    return np.where(q < 0.5, 1 - 6 * q**2 + 6 * q**3, 2 * (1 - q) ** 3)


POSITIONS = np.array([[c, r] for r in range(N) for c in range(N)], float)


def footprint(radius):
    def weights(x):
        s = kernel(np.linalg.norm(POSITIONS - np.array([x, 10.0]), axis=1) / radius)
        return s / s.sum()

    return weights


def report():
    C = compliance(laplacian())
    cases = [("barycentric", barycentric)] + [("footprint %.1f" % r, footprint(r)) for r in (1.0, 1.5, 2.0, 2.5)]
    print("weights          vertex 10 (8 edges)  vertex 9 (4 edges)")
    for name, weights in cases:
        k = {x: 1.0 / (weights(x) @ C @ weights(x)) for x in (8.5, 9.0, 9.5, 10.0, 10.5)}
        eight = k[10.0] / (0.5 * (k[9.5] + k[10.5])) - 1
        four = k[9.0] / (0.5 * (k[8.5] + k[9.5])) - 1
        print("%-16s %+18.1f %% %+17.1f %%" % (name, 100 * eight, 100 * four))


if __name__ == "__main__":
    report()
