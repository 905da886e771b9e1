#!/usr/bin/python3
"""Which start lattices a density kernel keeps still under pressure (doc/validation.md §2).

Below its free surface a resting column carries a positive multiplier lambda, and each
correction moves the particles down the gradient of sum_i lambda C_i, C_i = rho_i / rho0 - 1:
a displacement that lowers the particles' density sums is amplified. Displace a lattice by one
mode, u_i = a cos(k . X_i). To first order the density sums change by -a . S(k) sin(k . X_i),
S(k) = sum_r grad W(r) sin(k . r), and the constraint answers that change like any
compression. A polarisation a normal to S(k) is not seen at first order; at second order
every sum changes on average by

    (m / 2) a^T D(k) a,   D(k) = sum_{r != 0} (1 - cos(k . r)) H(r),   H = Hessian of W,

r running over the lattice vectors within the support. A negative eigenvalue of D(k) on the
polarisations the first order does not see means that mode lowers every density sum, so the
pressure drives it: the lattice rearranges however well the solve converges. This is a
linear, uniform-pressure criterion (no walls, no free surface); its use here is to compare
kernels and lattices, in units of d = 1 at the number density of one particle per d^3.

Usage: scripts/lattice_stability.py [--blend A ...] [h/d ...]
  h/d: support radii (default 2, the shipped one). --blend A adds the kernel
  A * Spiky + (1 - A) * Wendland C2 (both normalised, so the blend is too).
"""
import argparse
import itertools

import numpy as np


def spiky(h):
    """W = 15 / (pi h^6) (h - r)^3, the shipped density kernel (Kernels.h): W'(r), W''(r)."""
    c = 15.0 / (np.pi * h ** 6)
    return (lambda r: -3.0 * c * (h - r) ** 2), (lambda r: 6.0 * c * (h - r))


def wendland_c2(h):
    """W = 21 / (2 pi h^3) (1 - q)^4 (1 + 4 q), q = r / h (Wendland 1995): W'(r), W''(r)."""
    c = 21.0 / (2.0 * np.pi * h ** 3)
    return (lambda r: -20.0 * c * (r / h) * (1 - r / h) ** 3 / h,
            lambda r: c * (-20.0 * (1 - r / h) ** 3 + 60.0 * (r / h) * (1 - r / h) ** 2) / h ** 2)


def blend(a):
    """a * Spiky + (1 - a) * Wendland C2: W'(r), W''(r)."""
    def kernel(h):
        (s1, s2), (w1, w2) = spiky(h), wendland_c2(h)
        return (lambda r: a * s1(r) + (1 - a) * w1(r)), (lambda r: a * s2(r) + (1 - a) * w2(r))
    return kernel


def lattice(name, reach):
    """Lattice vectors (not 0) within `reach`, one particle per unit volume."""
    n = int(np.ceil(reach)) + 2
    cells = np.array(list(itertools.product(range(-n, n + 1), repeat=3)), dtype=float)
    if name == "simple cubic":
        points = cells
    else:  # face-centred cubic: 4 particles per cube of side 4^(1/3)
        basis = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
        points = (cells[:, None, :] + basis[None]).reshape(-1, 3) * 4 ** (1 / 3)
    length = np.linalg.norm(points, axis=1)
    return points[(length > 0) & (length < reach)]


def worst_mode(points, h, kernel, samples=24):
    """Smallest eigenvalue of D(k) over first-order-invisible polarisations, and its k."""
    d1, d2 = kernel(h)
    r = np.linalg.norm(points, axis=1)
    e = points / r[:, None]
    outer = e[:, :, None] * e[:, None, :]
    hessians = d2(r)[:, None, None] * outer + (d1(r) / r)[:, None, None] * (np.eye(3) - outer)
    gradients = d1(r)[:, None] * e
    worst = (np.inf, None)
    # k over the cube [0, 2 pi)^3 (covers the Brillouin zone of either lattice).
    for k in itertools.product(np.linspace(0, 2 * np.pi, samples, endpoint=False), repeat=3):
        k = np.array(k)
        if not k.any():
            continue
        phase = points @ k
        D = np.einsum("p,pij->ij", 1 - np.cos(phase), hessians)
        S = np.einsum("p,pi->i", np.sin(phase), gradients)
        if np.linalg.norm(S) > 1e-9 * np.abs(D).max():
            # Keep the polarisations normal to S(k): the plane spanned by two normals.
            basis = np.linalg.svd(S[None, :])[2][1:]
            D = basis @ D @ basis.T
        value = np.linalg.eigvalsh(D)[0]
        if value < worst[0]:
            worst = (value, k)
    return worst


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("factors", nargs="*", type=float, default=[2.0], help="h / d (default 2)")
    parser.add_argument("--blend", type=float, action="append", default=[],
                        help="also A * Spiky + (1 - A) * Wendland C2 (repeatable)")
    args = parser.parse_args()
    kernels = [("Spiky", spiky), ("Wendland C2", wendland_c2)]
    kernels += [(f"{a:g} Spiky", blend(a)) for a in args.blend]
    print("smallest eigenvalue of D(k) (negative: the lattice rearranges under pressure)")
    for h in args.factors:
        for kernel_name, kernel in kernels:
            for lattice_name in ("simple cubic", "face-centred cubic"):
                value, k = worst_mode(lattice(lattice_name, h), h, kernel)
                print(f"h = {h:g} d  {kernel_name:12s} {lattice_name:19s} {value:+.3e}"
                      f"  at k / pi = {np.round(k / np.pi, 2)}")


if __name__ == "__main__":
    main()
