#!/usr/bin/python3
"""How far apart two dam-break runs' surge fronts are: max and RMS of |dZ| over T <= 3,
each run's last front at or before T, sampled every 0.01 in T (the runs step at their own
times). Reads the dambreak_front.csv files of `pbf_bench --only dambreak`.

    front_compare.py DIR [DIR_HALF_DT] [--prefix dambreak_convergence]

prints, for the slab front (Z) and the sliding-window front (Z_sliding, where the CSV has
it): refinement between the resolution study's runs (coarse -> medium, medium -> fine) in
each folder, and, with a second folder run with dt halved, each run against itself at half
the dt. With --prefix dambreak_convergence it reads `pbf_bench --only convergence`'s
fronts instead and compares each resolution with the next finer one.
"""
import bisect
import csv
import os
import sys

T_MAX = 3.0
T_STEP = 0.01


def read_fronts(folder, prefix):
    """{run: {column: ([T...], [Z...])}} from DIR/PREFIX_front.csv, runs in file order."""
    runs = {}
    path = os.path.join(folder, prefix + "_front.csv")
    if not os.path.isfile(path):
        study = "convergence" if prefix == "dambreak_convergence" else "dambreak"
        sys.exit(f"front_compare.py: no {path} (run pbf_bench --out {folder} --only {study})")
    with open(path) as f:
        for row in csv.DictReader(f):
            run = runs.setdefault(row["run"], {})
            for column in ("Z", "Z_sliding"):
                if row.get(column) not in (None, ""):
                    T, Z = run.setdefault(column, ([], []))
                    T.append(float(row["T"]))
                    Z.append(float(row[column]))
    return runs


def front_at(curve, t):
    """The last front recorded at or before t."""
    T, Z = curve
    k = bisect.bisect_right(T, t + 1e-12) - 1
    return Z[max(k, 0)]


def difference(a, b):
    """(max, RMS) of |Z_a - Z_b| over 0 <= T <= T_MAX."""
    diffs = []
    for k in range(int(round(T_MAX / T_STEP)) + 1):
        t = k * T_STEP
        diffs.append(abs(front_at(a, t) - front_at(b, t)))
    return max(diffs), (sum(d * d for d in diffs) / len(diffs)) ** 0.5


def report(label, a, b, column):
    if column in a and column in b:
        worst, rms = difference(a[column], b[column])
        print(f"  {label:<52} max {worst:.3f} a   RMS {rms:.3f} a")


def main(argv):
    args = argv[1:]
    prefix = "dambreak"
    if "--prefix" in args:
        k = args.index("--prefix")
        if k + 1 >= len(args):
            sys.exit("front_compare.py: --prefix needs a value\n" + __doc__)
        prefix = args[k + 1]
        del args[k:k + 2]
    if len(args) not in (1, 2) or any(a.startswith("-") for a in args):
        sys.exit(__doc__)
    folders = args
    fronts = [read_fronts(f, prefix) for f in folders]
    if prefix == "dambreak":
        pairs = [("coarse d=0.04", "medium d=0.02"), ("medium d=0.02", "fine d=0.0125")]
    else:
        order = list(fronts[0])
        pairs = list(zip(order, order[1:]))
    for column in ("Z", "Z_sliding"):
        print(f"front {column}:")
        for folder, runs in zip(folders, fronts):
            for a, b in pairs:
                if a in runs and b in runs:
                    report(f"{a} -> {b} ({os.path.basename(folder.rstrip('/'))})", runs[a], runs[b], column)
        if len(fronts) == 2:
            for run in fronts[0]:
                if run in fronts[1]:
                    report(f"{run}: dt halved", fronts[0][run], fronts[1][run], column)


if __name__ == "__main__":
    main(sys.argv)
