#!/usr/bin/python3
"""A scene attaches its container to tf frame 'tank', but nobody publishes that frame: the
node warns (naming the frame) and keeps simulating with the container where it was."""
import threading
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Log

from fluid_test_util import stats_listener


class MissingFrameTest(unittest.TestCase):

    def test_missing_frame_warns_and_the_simulation_goes_on(self):
        warnings = []
        lock = threading.Lock()

        def on_log(msg):
            if msg.level == Log.WARN and "'tank'" in msg.msg:
                with lock:
                    warnings.append(msg.msg)

        sub = rospy.Subscriber('/rosout', Log, on_log, queue_size=100)
        stats = stats_listener()
        try:
            first = stats.next(timeout=30.0, condition=lambda m: m.sim_time > 0.2)
            later = stats.next(timeout=30.0, condition=lambda m: m.sim_time > first.sim_time + 0.5)
        finally:
            stats.close()
        self.assertGreater(later.step_count, first.step_count)
        self.assertGreater(later.particle_count, 0)
        deadline = time.time() + 15.0  # the warning is throttled (every 10 s)
        while time.time() < deadline:
            with lock:
                if warnings:
                    break
            time.sleep(0.2)
        sub.unregister()
        with lock:
            self.assertTrue(warnings, 'no WARN naming the missing frame on /rosout')


if __name__ == '__main__':
    rospy.init_node('test_missing_frame')
    rostest.rosrun('pbf_ros', 'missing_frame', MissingFrameTest)
