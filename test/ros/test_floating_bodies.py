#!/usr/bin/python3
"""Floating bodies in pbf_node (issue 12, part 3), floating_bodies scene at spacing 0.025: the
node publishes the bodies' poses on tf; after two simulated seconds the raft (500 kg/m^3)
floats at the water line, the stone (2000 kg/m^3) rests on the floor, and the buoy dropped
from above is in the water; the water's push on the raft comes on ~wrench/obstacle_0."""
import unittest

import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import WrenchStamped

from fluid_test_util import NODE, Latest, stats_listener

LEVEL = 0.2  # the water line before the bodies displace anything [m]


class FloatingBodiesTest(unittest.TestCase):

    def test_bodies_move_with_the_water_and_come_on_tf(self):
        stats = stats_listener()
        try:
            stats.next(timeout=60.0, condition=lambda m: m.sim_time > 2.0)
        finally:
            stats.close()
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        z = {}
        for frame in ('raft', 'stone', 'buoy'):
            t = buffer.lookup_transform('fluid_domain', frame, rospy.Time(0), rospy.Duration(10.0))
            z[frame] = t.transform.translation.z
        rospy.loginfo('body heights: %s', z)
        self.assertAlmostEqual(z['raft'], LEVEL, delta=0.04)   # its centre near the water line
        self.assertAlmostEqual(z['stone'], 0.05, delta=0.01)   # on the floor (radius 0.05)
        self.assertLess(z['buoy'], 0.3)                        # dropped from 0.35, now in the water
        self.assertGreater(z['buoy'], 0.1)                     # and not sunk
        push = Latest(NODE + '/wrench/obstacle_0', WrenchStamped).next(timeout=10.0)
        self.assertEqual(push.header.frame_id, 'raft')
        self.assertGreater(push.wrench.force.z, 0.0)  # the water holds the raft up


if __name__ == '__main__':
    rospy.init_node('test_floating_bodies')
    rostest.rosrun('pbf_ros', 'floating_bodies', FloatingBodiesTest)
