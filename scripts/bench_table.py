#!/usr/bin/python3
"""Median step times per build from scripts/bench_vs_baseline.sh's JSON files, and each
build's ratio to the baseline (baseline ms / build ms: > 1 means faster than the baseline).

    bench_table.py OUT_DIR BUILD...
"""
import glob
import json
import os
import re
import statistics
import sys


def common_name(run_name):
    """The benchmark's name as the baseline spells it: since the Gauss-Seidel solve (session
    20) this tree's names carry a gauss_seidel argument; 0, the Jacobi iterations, is the
    baseline's only solve."""
    return re.sub(r"/gauss_seidel:0(?=/|$)", "", run_name)


def medians(out_dir, build):
    """{benchmark name: [median real time in ms per round]} for one build."""
    times = {}
    for path in sorted(glob.glob(os.path.join(out_dir, build + "_*.json"))):
        with open(path) as f:
            data = json.load(f)
        for b in data["benchmarks"]:
            if b.get("aggregate_name") != "median":
                continue
            scale = {"ms": 1.0, "us": 1e-3, "ns": 1e-6, "s": 1e3}[b["time_unit"]]
            times.setdefault(common_name(b["run_name"]), []).append(b["real_time"] * scale)
    return times


def main():
    out_dir, builds = sys.argv[1], sys.argv[2:]
    table = {b: medians(out_dir, b) for b in builds}
    names = sorted({n for t in table.values() for n in t})
    print("| benchmark | " + " | ".join(f"{b} [ms/step]" for b in builds) +
          (" | " + " | ".join(f"baseline/{b}" for b in builds if b != "baseline")
           if "baseline" in builds else "") + " |")
    print("|---" * (1 + len(builds) + (len(builds) - 1 if "baseline" in builds else 0)) + "|")
    for n in names:
        med = {b: statistics.median(table[b][n]) for b in builds if n in table[b]}
        row = [f"{med[b]:.2f}" if b in med else "-" for b in builds]
        if "baseline" in med:
            row += [f"{med['baseline'] / med[b]:.2f}" if b in med else "-"
                    for b in builds if b != "baseline"]
        print(f"| {n} | " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
