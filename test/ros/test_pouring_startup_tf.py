#!/usr/bin/python3
"""The pouring arm's start pose reaches a tf listener that comes late, before /clock runs.
robot_state_publisher turns the trajectory's start pose into tf on /tf, which is not latched;
the fluid node's listener that subscribed after that first message used to wait its whole
~robot_tf_wait for the arm and leave its links out (robot_pouring failed now and then).

Nobody publishes /clock here. The test first sees the start pose's tf go out on /tf, then
starts a tf listener (its subscriber gets only what comes after) and waits for the cup."""
import threading
import time
import unittest

import rospy
import rostest
import tf2_ros
from tf2_msgs.msg import TFMessage

LINKS = ('upper_arm', 'forearm', 'cup')   # moved by the trajectory's joints
STARTUP_STAMP = 0.02                      # the trajectory's default ~startup_stamp [s]


def wait_for(condition, timeout):
    """Polls on the wall clock (simulated time does not run here)."""
    deadline = time.monotonic() + timeout
    while not condition() and time.monotonic() < deadline and not rospy.is_shutdown():
        time.sleep(0.02)
    return condition()


class PouringStartupTfTest(unittest.TestCase):

    def test_late_listener_gets_the_start_pose(self):
        first = threading.Event()
        sub = rospy.Subscriber('/tf', TFMessage, lambda m: first.set()
                               if any(t.child_frame_id == 'cup' for t in m.transforms) else None)
        self.assertTrue(wait_for(first.is_set, 30.0),
                        'robot_state_publisher sent no tf for the cup')
        self.assertTrue(rospy.Time.now().is_zero())  # still before /clock
        time.sleep(0.5)  # the first message is well behind us

        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        found = wait_for(lambda: all(buffer.can_transform('base_link', link, rospy.Time(0))
                                     for link in LINKS), 5.0)
        sub.unregister()
        self.assertTrue(found, 'a tf listener that started after the first message has no tf '
                        'for %s after 5 s' % ', '.join(l for l in LINKS if not buffer.can_transform(
                            'base_link', l, rospy.Time(0))))
        cup = buffer.lookup_transform('base_link', 'cup', rospy.Time(0))
        # The start pose (upright cup: the three pitch angles add up to 0), stamped at the
        # trajectory's start-up stamp, not at some time on a /clock that is not running.
        self.assertAlmostEqual(cup.header.stamp.to_sec(), STARTUP_STAMP, delta=1e-6)
        self.assertAlmostEqual(cup.transform.rotation.y, 0.0, delta=1e-6)


if __name__ == '__main__':
    rospy.init_node('test_pouring_startup_tf')
    rostest.rosrun('pbf_ros', 'pouring_startup_tf', PouringStartupTfTest)
