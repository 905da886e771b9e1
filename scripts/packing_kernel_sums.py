#!/usr/bin/python3
"""The density kernel's sum over the regular packings, at the same number density.

The solver's mass is calibrated on the cubic start lattice (SolverParams::densityMass): a
lattice particle sums to exactly rho0. A packing whose sum is lower at the same number
density must be denser in number to reach rho0. Under gravity, with a compression-only
constraint, a column that rearranges into such a packing falls: this prints by how much
(doc/calibration.md, the start-up). Printed for the solver's density kernel, Spiky, and for
Wendland C2 (doc/experiments/wendland_density_kernel.patch), on which the cubic lattice is
the densest packing at rho0 instead.

  scripts/packing_kernel_sums.py [--support H] [--blend A ...]
  H = h / d (default 2, the shipped factor); --blend A adds A * Spiky + (1 - A) * Wendland C2.
"""
import argparse
import itertools

import numpy as np


def spiky(r, h):
    return np.where(r < h, 15.0 / (np.pi * h**6) * np.clip(h - r, 0.0, None) ** 3, 0.0)


def wendland_c2(r, h):
    q = np.clip(r / h, 0.0, 1.0)
    return 21.0 / (2.0 * np.pi * h**3) * (1.0 - q) ** 4 * (1.0 + 4.0 * q)


def kernel_sum(kernel, basis, cell, h, scale=1.0):
    """Sum of W over the lattice (cell rows: primitive vectors, basis in cell coordinates) at
    one particle per unit volume times scale^-3, in units where that volume is 1."""
    per_volume = (len(basis) / abs(np.linalg.det(cell))) ** (1.0 / 3.0)
    cell = cell * per_volume * scale
    n = int(np.ceil(h / np.min(np.linalg.norm(cell, axis=1)))) + 2
    total = 0.0
    for ijk in itertools.product(range(-n, n + 1), repeat=3):
        for b in basis:
            total += float(kernel(np.linalg.norm((np.array(ijk) + b) @ cell), h))
    return total


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--support", type=float, default=2.0, help="h / d (default 2)")
    parser.add_argument("--blend", type=float, action="append", default=[],
                        help="also A * Spiky + (1 - A) * Wendland C2 (repeatable)")
    args = parser.parse_args()
    h = args.support
    eye = np.eye(3)
    hexagonal = np.array([[1.0, 0.0, 0.0], [0.5, np.sqrt(3) / 2, 0.0], [0.0, 0.0, np.sqrt(8.0 / 3.0)]])
    packings = {
        "simple cubic (the start lattice)": ([np.zeros(3)], eye),
        "body-centred cubic": ([np.zeros(3), np.full(3, 0.5)], eye),
        "face-centred cubic": ([np.zeros(3), np.array([0.5, 0.5, 0]), np.array([0.5, 0, 0.5]), np.array([0, 0.5, 0.5])], eye),
        "hexagonal close-packed": ([np.zeros(3), np.array([1 / 3, 1 / 3, 0.5])], hexagonal),
    }
    kernels = [("Spiky (the solver's)", spiky), ("Wendland C2 (the experiment)", wendland_c2)]
    kernels += [(f"{a:g} Spiky + {1 - a:g} Wendland C2", lambda r, h, a=a: a * spiky(r, h) + (1 - a) * wendland_c2(r, h))
                for a in args.blend]
    for kernel_name, kernel in kernels:
        cubic = kernel_sum(kernel, *packings["simple cubic (the start lattice)"], h)
        print(f"{kernel_name}, h = {h:g} d; sums times d^3 at one particle per d^3 (the continuum's: 1, plus the self term {float(kernel(0.0, h)):.4f})")
        print(f"{'packing':36s} {'sum':>8s} {'vs cubic':>9s} {'number density at the cubic sum':>32s}")
        for name, (basis, cell) in packings.items():
            total = kernel_sum(kernel, basis, cell, h)
            lo, hi = 0.95, 1.05  # the length scale whose sum is the cubic lattice's
            for _ in range(50):
                mid = 0.5 * (lo + hi)
                (lo, hi) = (mid, hi) if kernel_sum(kernel, basis, cell, h, mid) > cubic else (lo, mid)
            density = (0.5 * (lo + hi)) ** -3
            print(f"{name:36s} {total:8.5f} {100 * (total / cubic - 1):+8.3f} % {100 * (density - 1):+27.3f} % denser")
        print()

if __name__ == "__main__":
    main()
