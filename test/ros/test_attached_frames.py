#!/usr/bin/python3
"""A container attached to a moving tf frame carries the fluid: in a tank at rest the
fluid's mean horizontal velocity stays near 0; shaken along x by scripts/move_frame.py, the water
moves along x with it."""
import sys
import time
import unittest

import rospy
import rostest

from fluid_test_util import cloud_listener, cloud_points, mean, stats_listener


def largest_mean_vx(seconds):
    """Largest |mean vx| of the fluid over `seconds` of wall time."""
    clouds = cloud_listener()
    try:
        largest = 0.0
        deadline = time.time() + seconds
        while time.time() < deadline:
            points = cloud_points(clouds.next(timeout=10.0))
            largest = max(largest, abs(mean(p[3] for p in points)))
        return largest
    finally:
        clouds.close()


class AttachedFramesTest(unittest.TestCase):

    def test_moving_tank_carries_the_fluid(self):
        stats = stats_listener()
        try:
            stats.next(timeout=30.0, condition=lambda m: m.sim_time > 1.0)
        finally:
            stats.close()
        self.assertGreater(largest_mean_vx(3.0), 0.1)


if __name__ == '__main__':
    rospy.init_node('test_attached_frames')
    if '--baseline' in sys.argv:  # manual check: run without move_frame.py
        print('largest |mean vx| at rest: %.3f' % largest_mean_vx(3.0))
    else:
        rostest.rosrun('pbf_ros', 'attached_frames', AttachedFramesTest)
