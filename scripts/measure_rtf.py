#!/usr/bin/python3
"""Measures the real-time factor pbf_node achieves: listens to ~stats for a while and
divides the simulated time that passed by the wall time.

  rosrun pbf_ros measure_rtf.py [seconds=30] [node=/fluid]
"""
import sys
import time

import rospy
from pbf_ros.msg import SimulationStats


def main():
    duration = float(sys.argv[1]) if len(sys.argv) > 1 else 30.0
    node = sys.argv[2] if len(sys.argv) > 2 else "/fluid"
    rospy.init_node("measure_rtf", anonymous=True)
    samples = []
    rospy.Subscriber(node + "/stats", SimulationStats, lambda m: samples.append((time.time(), m)))
    time.sleep(duration)
    if len(samples) < 2:
        print("measure_rtf: fewer than 2 messages on %s/stats in %.0f s" % (node, duration))
        return 1
    (w0, first), (w1, last) = samples[0], samples[-1]
    msgs = [m for _, m in samples]
    mean = lambda values: sum(values) / len(values)
    print("%d particles: real-time factor %.3f over %.1f s wall (node-reported mean %.3f); "
          "step %.1f ms, %.1f iterations, dt %.2f ms, render %.1f ms" % (
              last.particle_count, (last.sim_time - first.sim_time) / (w1 - w0), w1 - w0,
              mean([m.real_time_factor for m in msgs]), mean([m.time_total_ms for m in msgs]),
              mean([m.iterations for m in msgs]), 1000.0 * mean([m.dt for m in msgs]),
              mean([m.time_render_ms for m in msgs])))
    return 0


if __name__ == "__main__":
    sys.exit(main())
