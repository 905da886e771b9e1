#!/usr/bin/python3
"""Measures the real-time factor pbf_node achieves: listens to ~stats and divides the
simulated time that passed by the wall time.

  rosrun pbf_ros measure_rtf.py [seconds=30] [node=/fluid] [--sim-window A B]

Without --sim-window: over the next `seconds` of wall time, wherever the simulation is.
With it: over the simulated interval [A, B] s (from the first message at or after A to the
first at or after B), waiting at most `seconds` for B. A scene's cost changes as it flows
(a dam break's first second takes smaller steps than its third), so two builds of unequal
speed are compared over the same simulated interval, not the same wall-clock window.
"""
import argparse
import math
import sys
import time

import rospy
from pbf_ros.msg import SimulationStats


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("seconds", type=float, nargs="?", default=30.0)
    parser.add_argument("node", nargs="?", default="/fluid")
    parser.add_argument("--sim-window", type=float, nargs=2, metavar=("A", "B"))
    args = parser.parse_args(rospy.myargv()[1:])
    if not (math.isfinite(args.seconds) and args.seconds > 0.0):
        parser.error("seconds must be a finite number > 0, got %r" % args.seconds)
    if args.sim_window and not (all(math.isfinite(v) for v in args.sim_window)
                                and 0.0 <= args.sim_window[0] < args.sim_window[1]):
        parser.error("--sim-window needs 0 <= A < B")
    rospy.init_node("measure_rtf", anonymous=True)
    samples = []
    rospy.Subscriber(args.node + "/stats", SimulationStats, lambda m: samples.append((time.time(), m)))
    deadline = time.time() + args.seconds
    if args.sim_window:
        start, end = args.sim_window
        while time.time() < deadline and not (samples and samples[-1][1].sim_time >= end):
            time.sleep(0.1)
        window = [s for s in samples if s[1].sim_time >= start]
        reached = [s for s in window if s[1].sim_time >= end]
        if not window or not reached:
            print("measure_rtf: %s did not reach simulated time %.2f s within %.0f s" % (
                args.node, end, args.seconds))
            return 1
        samples = window[:window.index(reached[0]) + 1]
    else:
        time.sleep(args.seconds)
    if len(samples) < 2:
        print("measure_rtf: fewer than 2 messages on %s/stats in %.0f s" % (args.node, args.seconds))
        return 1
    (w0, first), (w1, last) = samples[0], samples[-1]
    msgs = [m for _, m in samples]
    mean = lambda values: sum(values) / len(values)
    print("%d particles: real-time factor %.3f over %.1f s wall, simulated %.2f-%.2f s (node-reported "
          "mean %.3f); step %.1f ms, %.1f iterations, dt %.2f ms, render %.1f ms" % (
              last.particle_count, (last.sim_time - first.sim_time) / (w1 - w0), w1 - w0,
              first.sim_time, last.sim_time, mean([m.real_time_factor for m in msgs]),
              mean([m.time_total_ms for m in msgs]), mean([m.iterations for m in msgs]),
              1000.0 * mean([m.dt for m in msgs]), mean([m.time_render_ms for m in msgs])))
    return 0


if __name__ == "__main__":
    sys.exit(main())
