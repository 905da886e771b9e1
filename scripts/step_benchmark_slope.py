#!/usr/bin/python3
"""Scaling slopes of pbf_step_benchmark: time per step against particles, log-log.

Issue 10 asks for the step benchmark's slope from 20k to 320k particles (at most 1.05).
Reads the JSON that Google Benchmark writes with --benchmark_out, for example:

  GOMP_SPINCOUNT=2000 OMP_WAIT_POLICY=passive pbf_step_benchmark \\
      --benchmark_filter='BM_(DamBreakStep|GaussSeidelScaling)/kparticles:[0-9]+/threads:[12]/boundary:1/' \\
      --benchmark_repetitions=3 --benchmark_report_aggregates_only=true \\
      --benchmark_out=run1.json --benchmark_out_format=json
  scripts/step_benchmark_slope.py run1.json [run2.json ...]

BM_DamBreakStep takes 4 Jacobi iterations per step (the baseline's solve, which the issue's
ratios compare), BM_GaussSeidelScaling 4 Gauss-Seidel sweeps (the shipped solve). For each
benchmark and thread count it prints the medians' ms per step, ns per particle and the
least-squares slope of log(ms) against log(particles) over every size, per file.
"""
import json
import re
import sys
from collections import defaultdict

from plot_bench import loglog_slope  # the scaling study's fit (scripts/plot_bench.py)

NAME = re.compile(r"^(BM_\w+)/kparticles:(\d+)/threads:(\d+)/")


def to_ms(value, unit):
    return value * {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[unit]


def medians(path):
    """{(benchmark, threads): {particles: ms per step}} from one file's median aggregates."""
    with open(path) as f:
        runs = json.load(f)["benchmarks"]
    table = defaultdict(dict)
    for run in runs:
        if run.get("run_type") != "aggregate" or run.get("aggregate_name") != "median":
            continue
        m = NAME.match(run["name"])
        if m is None or "particles" not in run:
            continue
        table[(m.group(1), int(m.group(3)))][run["particles"]] = to_ms(run["real_time"], run["time_unit"])
    return table


def main(paths):
    if not paths:
        print(__doc__)
        return 2
    for path in paths:
        print(f"{path}:")
        table = medians(path)
        if not table:
            print("  no median aggregates of BM_.../kparticles:K/threads:T/ (run with --benchmark_repetitions)")
            continue
        for (bench, threads), by_size in sorted(table.items()):
            sizes = sorted(by_size)
            ms = [by_size[n] for n in sizes]
            cells = ", ".join(f"{n / 1000:.0f}k {t:.1f} ms ({t * 1e6 / n:.0f} ns)" for n, t in zip(sizes, ms))
            slope = loglog_slope(sizes, ms) if len(sizes) > 1 else float("nan")
            print(f"  {bench}, {threads} thread(s): {cells}; slope {slope:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
