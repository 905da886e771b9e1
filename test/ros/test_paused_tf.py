#!/usr/bin/python3
"""Floating bodies' tf while paused on the node's own /clock: resets and steps while paused
never send a body's pose twice at one stamp (tf2 would refuse it, TF_REPEATED_DATA), and the
node does not log TF_REPEATED_DATA."""
import collections
import threading
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Log
from std_srvs.srv import SetBool, Trigger
from tf2_msgs.msg import TFMessage

from fluid_test_util import NODE, stats_listener, wait_connected

BODIES = ('raft', 'stone', 'buoy')


class TfRecorder:
    """Every (child frame, stamp) the node sends on /tf, and the node's rosout lines."""

    def __init__(self):
        self.lock = threading.Lock()
        self.sent = collections.Counter()
        self.logs = []
        self.tf = rospy.Subscriber('/tf', TFMessage, self._tf, queue_size=1000)
        self.rosout = rospy.Subscriber('/rosout', Log, self._log, queue_size=1000)
        # Nothing the node sends from here on is missed (it may still be starting).
        wait_connected(self.tf, timeout=30.0)
        wait_connected(self.rosout, timeout=30.0)

    def _tf(self, msg):
        if msg._connection_header.get('callerid') != NODE:
            return
        with self.lock:
            for t in msg.transforms:
                self.sent[(t.child_frame_id, t.header.stamp.to_nsec())] += 1

    def _log(self, msg):
        with self.lock:
            self.logs.append(msg.msg)

    def repeated(self):
        with self.lock:
            return [key for key, n in self.sent.items() if n > 1]


class PausedTfTest(unittest.TestCase):

    def test_no_body_pose_twice_at_one_stamp(self):
        rec = TfRecorder()
        stats = stats_listener()
        stats.next(timeout=30.0)  # the node is up (paused since start)
        pause = rospy.ServiceProxy(NODE + '/pause', SetBool)
        reset = rospy.ServiceProxy(NODE + '/reset', Trigger)
        step = rospy.ServiceProxy(NODE + '/step', Trigger)
        # A reset while paused at start-up, then run, pause, and reset again (the clock keeps
        # the last step's time), twice; a step between them sends at a new stamp.
        self.assertTrue(reset().success)
        self.assertTrue(pause(False).success)
        stats.next(timeout=30.0, condition=lambda m: m.sim_time > 0.2)
        self.assertTrue(pause(True).success)
        for call in (reset, reset, step, reset):
            answer = call()
            self.assertTrue(answer.success, answer.message)
        time.sleep(1.0)  # what was sent arrives
        stats.close()
        with rec.lock:
            frames = {frame for frame, _ in rec.sent}
            repeated_logs = [line for line in rec.logs if 'TF_REPEATED_DATA' in line]
        self.assertEqual(frames, set(BODIES))
        self.assertEqual(rec.repeated(), [])
        self.assertEqual(repeated_logs, [])


if __name__ == '__main__':
    rospy.init_node('test_paused_tf')
    rostest.rosrun('pbf_ros', 'paused_tf', PausedTfTest)
