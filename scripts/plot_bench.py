#!/usr/bin/python3
"""Plots and a Markdown summary from the CSV files pbf_bench and pbf_stress write.

    scripts/plot_bench.py [FOLDER]      (default: bench_out)

Reads whatever of dambreak_front.csv, dambreak_summary.csv, sweep.csv, scaling.csv,
tank.csv, stress.csv and stress_energy.csv is in FOLDER and writes next to them:
dambreak_front.png, hydrostatic.png, pareto.png, scaling.png, stress_energy.png and
summary.md (the tables of doc/validation.md).
Needs Debian's python3-matplotlib (run with /usr/bin/python3, not a pyenv python).
"""
import csv
import math
import os
import sys

import matplotlib
matplotlib.use("Agg")  # headless: no display needed
import matplotlib.pyplot as plt  # noqa: E402

DPI = 80  # small PNGs: the README embeds them and they are committed
# The sweep setting proposed as the shipped defaults (marked with a star in the Pareto plot).
CHOSEN = "shipped"


def read_csv(folder, name):
    path = os.path.join(folder, name)
    if not os.path.exists(path):
        return None
    with open(path, newline="") as f:
        return list(csv.DictReader(row for row in f if not row.startswith("#")))


def num(row, key):
    try:
        return float(row[key])
    except (KeyError, ValueError):
        return float("nan")


def pareto_front(points):
    """Indices of the points no other point beats in both coordinates (both minimised)."""
    front = []
    for i, (x, y) in enumerate(points):
        if math.isnan(x) or math.isnan(y):
            continue
        dominated = any(
            (x2 <= x and y2 <= y and (x2 < x or y2 < y))
            for j, (x2, y2) in enumerate(points) if j != i and not (math.isnan(x2) or math.isnan(y2)))
        if not dominated:
            front.append(i)
    return sorted(front, key=lambda i: points[i][0])


def save(fig, folder, name):
    path = os.path.join(folder, name)
    fig.savefig(path, dpi=DPI, bbox_inches="tight")
    plt.close(fig)
    print(f"wrote {path} ({os.path.getsize(path) // 1024} kB)")


def reference_front(folder):
    """Martin & Moyce's front: from the study's folder, else the repository's copy."""
    ref = read_csv(folder, "martin_moyce_1952_surge_front.csv")
    if ref is None:
        here = os.path.dirname(os.path.abspath(__file__))
        ref = read_csv(os.path.join(here, "..", "doc", "validation"), "martin_moyce_1952_surge_front.csv")
    return ref


def finish_front_axes(ax, ref, title):
    """The reference points, the axes and the legend every surge-front plot shares."""
    if ref:
        ax.plot([num(r, "T") for r in ref], [num(r, "Z") for r in ref], "ko", ms=5,
                label="Martin & Moyce 1952 (n$^2$=2)")
    ax.set_xlim(0, 3.4)
    ax.set_ylim(0.9, 4.3)
    ax.set_xlabel("T = t sqrt(2g/a)")
    ax.set_ylabel("Z = front / a")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left")


def plot_dambreak(folder, md):
    fronts = read_csv(folder, "dambreak_front.csv")
    summary = read_csv(folder, "dambreak_summary.csv")
    ref = reference_front(folder)
    if not fronts or not summary:
        return
    fig, ax = plt.subplots(figsize=(7, 4.2))
    runs = [row["run"] for row in summary]
    shifts = {row["run"]: num(row, "best_shift") for row in summary}
    for run in runs:
        T = [num(r, "T") for r in fronts if r["run"] == run]
        Z = [num(r, "Z") for r in fronts if r["run"] == run]
        line, = ax.plot(T, Z, lw=1.5, label=f"{run}")
        if "default" in run:
            s = shifts[run]
            ax.plot([t + s for t in T], Z, lw=1.2, ls="--", color=line.get_color(),
                    label=f"{run}, shifted +{s:.2f}")
    finish_front_axes(ax, ref, "Dam break: surge front")
    save(fig, folder, "dambreak_front.png")
    md.append("### Dam break against Martin & Moyce (1952)\n")
    md.append("| run | particles | a/d | RMS of Z, no shift | fitted shift | RMS with shift | wall s / sim s | "
              "no shift, front = 1/4 row / full row | fitted shift, 1/4 row / full row | "
              "sliding front: no shift / shift / shifted |")
    md.append("|---|---|---|---|---|---|---|---|---|---|")
    for r in summary:
        md.append(f"| {r['run']} | {int(num(r, 'particles'))} | {num(r, 'a_over_d'):.0f} | "
                  f"{num(r, 'rms_no_shift'):.3f} a | +{num(r, 'best_shift'):.2f} | "
                  f"{num(r, 'rms_shifted'):.3f} a | {num(r, 'wall_per_sim_s'):.1f} | "
                  f"{num(r, 'rms_no_shift_quarter_row'):.3f} / {num(r, 'rms_no_shift_full_row'):.3f} a | "
                  f"+{num(r, 'shift_quarter_row'):.2f} / +{num(r, 'shift_full_row'):.2f} | "
                  + (f"{num(r, 'rms_no_shift_sliding'):.3f} a / +{num(r, 'shift_sliding'):.2f} / "
                     f"{num(r, 'rms_shifted_sliding'):.3f} a |" if "shift_sliding" in r else "– |"))
    md.append("\nRMS over the tabulated T <= 3; the shift delays the simulated curve by the fitted "
              "gate-release time (searched in [0, 0.4]).\n")


def plot_convergence(folder, md):
    """pbf_bench --only convergence: the slab's front at a/d = 10 ... 64 and the fitted delays."""
    fronts = read_csv(folder, "dambreak_convergence_front.csv")
    summary = read_csv(folder, "dambreak_convergence_summary.csv")
    if not fronts or not summary:
        return
    ref = reference_front(folder)
    fig, ax = plt.subplots(figsize=(7, 4.2))
    for row in summary:
        run = row["run"]
        T = [num(r, "T") for r in fronts if r["run"] == run]
        Z = [num(r, "Z_sliding") for r in fronts if r["run"] == run]
        ax.plot(T, Z, lw=1.2, label=f"{run} (sliding-window front)")
    finish_front_axes(ax, ref, "Dam break: convergence of the 0.2 m slab")
    save(fig, folder, "dambreak_convergence.png")
    md.append("### Dam break: convergence of the slab\n")
    md.append("| run | particles | RMS no shift | fitted shift | RMS shifted | sliding front: no shift / shift / shifted | wall s / sim s |")
    md.append("|---|---|---|---|---|---|---|")
    for r in summary:
        md.append(f"| {r['run']} | {int(num(r, 'particles'))} | {num(r, 'rms_no_shift'):.3f} a | "
                  f"+{num(r, 'best_shift'):.2f} | {num(r, 'rms_shifted'):.3f} a | "
                  f"{num(r, 'rms_no_shift_sliding'):.3f} a / +{num(r, 'shift_sliding'):.2f} / "
                  f"{num(r, 'rms_shifted_sliding'):.3f} a | {num(r, 'wall_per_sim_s'):.1f} |")
    md.append("")


def plot_hydrostatic(folder, md):
    sweep = read_csv(folder, "sweep.csv")
    if not sweep:
        return
    series = [("iterations", "fixed iterations (sweeps; Jacobi: x)", "max_iterations", False),
              ("tolerance", "density tolerance (1..30 sweeps)", "density_tolerance", True)]
    metrics = [("hydro_avg_err", "avg density error [%]", 100), ("hydro_max_err", "max density error [%]", 100),
               ("hydro_height_loss", "column height loss [%]", 100), ("hydro_speed_max", "residual max speed [m/s]", 1)]
    fig, axes = plt.subplots(2, 4, figsize=(13, 5.5))
    for row, (group, label, key, logx) in enumerate(series):
        rows = sorted([r for r in sweep if r["group"] == group], key=lambda r: num(r, key))
        x = [num(r, key) for r in rows]
        for col, (metric, mlabel, scale) in enumerate(metrics):
            ax = axes[row][col]
            ax.plot(x, [scale * num(r, metric) for r in rows], "o-", ms=4)
            if group == "iterations":  # the Jacobi solve at fixed counts, for comparison
                jac = sorted([r for r in sweep if r["name"].startswith("jacobi_iter")], key=lambda r: num(r, key))
                ax.plot([num(r, key) for r in jac], [scale * num(r, metric) for r in jac], "x--", ms=5, color="gray")
            if logx:
                ax.set_xscale("log")
                ax.set_xticks(x)
                ax.set_xticklabels([f"{v:g}" for v in x], fontsize=7)
                ax.minorticks_off()
                ax.invert_xaxis()
            if metric == "hydro_avg_err":
                ax.axhline(0.5, color="r", ls="--", lw=1)  # the target
            ax.set_xlabel(label, fontsize=8)
            ax.set_ylabel(mlabel, fontsize=8)
            ax.grid(alpha=0.3)
            if metric in ("hydro_avg_err", "hydro_max_err", "hydro_speed_max"):
                ax.set_yscale("log")
                if logx:
                    ax.minorticks_off()
                    ax.set_xticks(x)
    fig.suptitle("Hydrostatic tank (0.3 m of water, d = 0.02), Gauss-Seidel solve, measured over the last 0.5 s of 1.5 s")
    fig.tight_layout()
    save(fig, folder, "hydrostatic.png")
    md.append("### Hydrostatic tank\n")
    md.append("| setting | mean iterations | avg density error | max density error | height loss | "
              "residual max / rms speed | wall s / sim s |")
    md.append("|---|---|---|---|---|---|---|")
    for r in sweep:
        if r["group"] not in ("iterations", "tolerance", "jacobi") and r["name"] != CHOSEN:
            continue
        md.append(f"| {r['name']} | {num(r, 'hydro_mean_iterations'):.1f} | {100 * num(r, 'hydro_avg_err'):.3f} % | "
                  f"{100 * num(r, 'hydro_max_err'):.2f} % | {100 * num(r, 'hydro_height_loss'):.2f} % | "
                  f"{num(r, 'hydro_speed_max'):.3f} / {num(r, 'hydro_speed_rms'):.4f} m/s | "
                  f"{num(r, 'hydro_wall_per_sim'):.2f} |")
    md.append("")


def plot_pareto(folder, md):
    sweep = read_csv(folder, "sweep.csv")
    if not sweep:
        return
    rows = [r for r in sweep if r["group"] != "reference"]
    panels = [("hydro_wall_per_sim", "hydro_avg_err", "(a) hydrostatic avg density error [%]", 100),
              ("dam_wall_per_sim", "dam_rms_no_shift", "(b) dam-break front RMS, no shift [a]", 1),
              ("dam_wall_per_sim", "dam_deviation", "(c) dam break: deviation from converged run [a]", 1)]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
    groups = sorted(set(r["group"] for r in rows))
    markers = dict(zip(groups, "osD^v<>p*"))
    md.append("### Pareto fronts (run time against error)\n")
    for ax, (xkey, ykey, label, scale) in zip(axes, panels):
        pts = [(num(r, xkey), scale * num(r, ykey)) for r in rows]
        for g in groups:
            sel = [i for i, r in enumerate(rows) if r["group"] == g]
            ax.plot([pts[i][0] for i in sel], [pts[i][1] for i in sel], markers[g], ms=5, label=g, alpha=0.8)
        front = pareto_front(pts)
        ax.plot([pts[i][0] for i in front], [pts[i][1] for i in front], "k-", lw=1, label="Pareto front")
        # The same front without the resolution group: the choice at the default spacing.
        same_d = [i for i, r in enumerate(rows) if r["group"] != "resolution"]
        front_d = [same_d[k] for k in pareto_front([pts[i] for i in same_d])]
        ax.plot([pts[i][0] for i in front_d], [pts[i][1] for i in front_d], "k--", lw=0.8,
                label="Pareto front at d = 0.02")
        for i in sorted(set(front) | set(front_d)):
            ax.annotate(rows[i]["name"], pts[i], fontsize=6, xytext=(3, 3), textcoords="offset points")
        chosen = [i for i, r in enumerate(rows) if r["name"] == CHOSEN]
        if chosen:
            ax.plot([pts[chosen[0]][0]], [pts[chosen[0]][1]], "r*", ms=12, label=f"chosen: {CHOSEN}")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall-clock s per simulated s")
        ax.set_title(label, fontsize=9)
        ax.grid(alpha=0.3, which="both")
        md.append(f"{label}: front = " + ", ".join(
            f"{rows[i]['name']} ({pts[i][0]:.2f} s/s, {pts[i][1]:.3g})" for i in front) + "\n")
        md.append(f"{label}, d = 0.02 only: front = " + ", ".join(
            f"{rows[i]['name']} ({pts[i][0]:.2f} s/s, {pts[i][1]:.3g})" for i in front_d) + "\n")
    axes[0].legend(fontsize=7)
    fig.tight_layout()
    save(fig, folder, "pareto.png")
    md.append("| setting | group | hydro wall (cpu) s/s | avg err | dam wall (cpu) s/s | mean iter | front RMS | RMS shifted | deviation |")
    md.append("|---|---|---|---|---|---|---|---|---|")
    for r in sweep:
        md.append(f"| {r['name']} | {r['group']} | {num(r, 'hydro_wall_per_sim'):.2f} ({num(r, 'hydro_cpu_per_sim'):.2f}) | "
                  f"{100 * num(r, 'hydro_avg_err'):.3f} % | {num(r, 'dam_wall_per_sim'):.2f} ({num(r, 'dam_cpu_per_sim'):.2f}) | "
                  f"{num(r, 'dam_mean_iterations'):.1f} | {num(r, 'dam_rms_no_shift'):.3f} | "
                  f"{num(r, 'dam_rms_shifted'):.3f} | {num(r, 'dam_deviation'):.3f} |")
    md.append("")


def loglog_slope(xs, ys):
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    sxx = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / sxx if sxx > 0 else float("nan")


def plot_scaling(folder, md):
    rows = read_csv(folder, "scaling.csv")
    if not rows:
        return
    fig, ax = plt.subplots(figsize=(6, 4.2))
    md.append("### Scaling (ms per step, dam-break column at rest, 4 iterations)\n")
    md.append("| particles | " + " | ".join(f"{t} thread(s)" for t in sorted(set(int(num(r, 'threads')) for r in rows))) + " |")
    threads = sorted(set(int(num(r, "threads")) for r in rows))
    md.append("|---|" + "---|" * len(threads))
    slopes, slopes_from_20k = {}, {}
    for t in threads:
        sel = [r for r in rows if int(num(r, "threads")) == t]
        x = [num(r, "particles") for r in sel]
        y = [num(r, "ms_per_step") for r in sel]
        slopes[t] = loglog_slope(x, y)
        # Issue 10's range: from 20 000 particles up.
        big = [(a, b) for r, a, b in zip(sel, x, y) if num(r, "target_particles") >= 20000]
        slopes_from_20k[t] = loglog_slope([a for a, _ in big], [b for _, b in big]) if len(big) > 1 else float("nan")
        ax.plot(x, y, "o-", label=f"{t} thread(s): slope {slopes[t]:.2f}")
    for target in sorted(set(int(num(r, "target_particles")) for r in rows)):
        cells = []
        for t in threads:
            v = [num(r, "ms_per_step") for r in rows if int(num(r, "threads")) == t and int(num(r, "target_particles")) == target]
            cells.append(f"{v[0]:.1f}" if v else "-")
        n = [num(r, "particles") for r in rows if int(num(r, "target_particles")) == target][0]
        md.append(f"| {int(n)} | " + " | ".join(cells) + " |")
    md.append("\nlog-log slope of ms/step against particles: " +
              ", ".join(f"{t} thread(s) {s:.2f}" for t, s in slopes.items()) +
              "; from 20 000 particles: " +
              ", ".join(f"{t} thread(s) {s:.2f}" for t, s in slopes_from_20k.items()) + "\n")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("particles")
    ax.set_ylabel("ms per step")
    ax.set_title("Time per step (4 iterations)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)
    save(fig, folder, "scaling.png")


def table_tank(folder, md):
    rows = read_csv(folder, "tank.csv")
    if not rows:
        return
    md.append("### Hydrostatic tank: start-up, walls, resolution and dt (`pbf_bench --only tank`)\n")
    md.append("| run | start-up max speed (first 0.05 s) | level loss (of the mean height) | bulk particles per d^3 | avg density error | rho/rho0 inside / face / edge / corner | first layer from its wall |")
    md.append("|---|---|---|---|---|---|---|")
    for r in rows:
        first = f" ({num(r, 'first_steps_speed_max'):.3f})" if "first_steps_speed_max" in r else ""
        bulk = f"{num(r, 'bulk_number_density'):.4f}" if "bulk_number_density" in r else "-"
        mean = f" ({100 * num(r, 'mean_height_loss'):.2f} %)" if "mean_height_loss" in r else ""
        md.append(f"| {r['run']} | {num(r, 'startup_speed_max'):.3f}{first} m/s | {100 * num(r, 'height_loss'):.2f} %{mean} | "
                  f"{bulk} | {100 * num(r, 'avg_density_error'):.3f} % | {num(r, 'interior_density'):.4f} / "
                  f"{num(r, 'face_density'):.4f} / {num(r, 'edge_density'):.4f} / {num(r, 'corner_density'):.4f} | "
                  f"{num(r, 'wall_gap'):.2f} d |")
    md.append("")


def plot_stress(folder, md):
    rows = read_csv(folder, "stress.csv") or read_csv(folder, "stress_reduced.csv")
    energy = read_csv(folder, "stress_energy.csv") or read_csv(folder, "stress_energy_reduced.csv")
    if rows:
        md.append("### Stress matrix (`pbf_stress`)\n")
        md.append("| case | setup | particles | steps | sim s | finite | inside | completed | energy bound | max E_kin / bound | end E_kin / settled bound | result |")
        md.append("|---|---|---|---|---|---|---|---|---|---|---|---|")
        for r in rows:
            if r["first_failure"].startswith("skipped"):  # pbf_stress --set conflicts with its settings
                md.append(f"| {r['case']} | {r['setup']} | - | - | - | - | - | - | - | - | - | {r['first_failure']} |")
                continue
            ok = lambda k: "yes" if r[k] == "1" else "**no**"
            settled = num(r, "settled_bound_J")
            end = f"{num(r, 'final_kinetic_J') / settled:.3f}" if settled > 0 else "-"
            md.append(f"| {r['case']} | {r['setup']} | {r['particles']} | {r['steps']} | {num(r, 'sim_s'):.2f} | "
                      f"{ok('finite')} | {ok('inside')} | {ok('completed')} | {r['bound']} | "
                      f"{num(r, 'max_kinetic_J') / num(r, 'bound_J'):.3f} | {end} | "
                      f"{'PASS' if r['pass'] == '1' else '**FAIL**: ' + r['first_failure']} |")
        md.append("")
    if energy:
        fig, ax = plt.subplots(figsize=(7, 4.2))
        for case in dict.fromkeys(r["case"] for r in energy):
            sel = [r for r in energy if r["case"] == case]
            t = [num(r, "t") for r in sel]
            ratio = [max(num(r, "kinetic_J") / num(r, "bound_J"), 1e-8) for r in sel]
            ax.plot(t, ratio, lw=1, label=case)
        ax.axhline(1.0, color="k", ls="--", lw=1)
        ax.set_xscale("symlog", linthresh=0.01)
        ax.set_xlim(left=0)
        ax.set_yscale("log")
        ax.set_xlabel("simulated time [s]")
        ax.set_ylabel("E_kin / bound")
        ax.set_title("Stress cases: kinetic energy against its bound")
        ax.grid(alpha=0.3, which="both")
        ax.legend(fontsize=5, ncol=2)
        save(fig, folder, "stress_energy.png")


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "bench_out"
    if not os.path.isdir(folder):
        sys.exit(f"plot_bench.py: no folder '{folder}' (run pbf_bench --out {folder} first)")
    md = ["<!-- generated by scripts/plot_bench.py -->\n"]
    for plot in (plot_dambreak, plot_convergence, plot_hydrostatic, table_tank, plot_pareto, plot_scaling, plot_stress):
        try:
            plot(folder, md)
        except Exception as e:  # one broken CSV must not cost the other plots
            print(f"plot_bench.py: {plot.__name__}: {e}", file=sys.stderr)
            raise
    with open(os.path.join(folder, "summary.md"), "w") as f:
        f.write("\n".join(md) + "\n")
    print(f"wrote {os.path.join(folder, 'summary.md')}")


if __name__ == "__main__":
    main()
