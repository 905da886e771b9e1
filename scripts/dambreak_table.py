#!/usr/bin/python3
"""Table of scripts/bench_vs_baseline.sh --dambreak-1m3: per build and density tolerance,
the median over rounds of wall seconds per simulated second, the steps per simulated second,
and the average density error the run reported (mean of pbf_run's 0.1 s samples, so the
tolerances can be seen to be matched); then the baseline's time over each build's (> 1:
faster than the baseline).

    dambreak_table.py OUT_DIR BUILD...
"""
import glob
import os
import re
import statistics
import sys

FINAL = re.compile(r"pbf_run: ([0-9.]+) s simulated in ([0-9.]+) s wall .*?, (\d+) steps")


def parse(path):
    """(wall s per simulated s, steps per simulated s, mean sampled average error in %)."""
    errors, final = [], None
    with open(path) as f:
        for line in f:
            cols = line.split()
            if len(cols) == 9 and re.fullmatch(r"\d+", cols[1]):
                errors.append(float(cols[4]))
            m = FINAL.search(line)
            if m:
                final = m
    if final is None:
        raise SystemExit(f"dambreak_table.py: {path} has no final line (run failed?)")
    sim, wall, steps = float(final.group(1)), float(final.group(2)), int(final.group(3))
    return wall / sim, steps / sim, statistics.mean(errors[1:]) if len(errors) > 1 else float("nan")


def main():
    out_dir, builds = sys.argv[1], sys.argv[2:]
    rows = {}
    for path in glob.glob(os.path.join(out_dir, "*_tol*_*.txt")):
        build, rest = os.path.basename(path).split("_tol", 1)
        tol = rest.rsplit("_", 1)[0]
        rows.setdefault((tol, build), []).append(parse(path))
    # "fast" (bench_vs_baseline.sh --fast) is filed under the tolerance it is compared at,
    # having been asked for its own: its error column says what it reached.
    print("| tolerance (compared at) | build | wall s / simulated s | steps / simulated s | avg density error | baseline / build |")
    print("|---|---|---|---|---|---|")
    for tol in sorted({t for t, _ in rows}, key=float, reverse=True):
        base = statistics.median(r[0] for r in rows.get((tol, "baseline"), [(float("nan"),)] ))
        for build in builds:
            runs = rows.get((tol, build))
            if not runs:
                continue
            wall = statistics.median(r[0] for r in runs)
            steps = statistics.median(r[1] for r in runs)
            err = statistics.median(r[2] for r in runs)
            print(f"| {float(tol) * 100:.2f} % | {build} | {wall:.1f} ({len(runs)} runs: "
                  f"{', '.join(f'{r[0]:.1f}' for r in runs)}) | {steps:.0f} | {err:.3f} % | {base / wall:.2f}x |")


if __name__ == "__main__":
    main()
