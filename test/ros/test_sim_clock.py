#!/usr/bin/python3
"""~publish_clock: /clock follows the simulation, stops while paused, and stamps the stats."""
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Clock
from std_srvs.srv import SetBool

from fluid_test_util import NODE, Latest, stats_listener


class SimClockTest(unittest.TestCase):

    def test_clock_follows_the_simulation_and_stops_while_paused(self):
        clock = Latest('/clock', Clock)
        stats = stats_listener()
        pause = rospy.ServiceProxy(NODE + '/pause', SetBool)
        rospy.wait_for_service(NODE + '/pause', timeout=30.0)
        try:
            first = clock.next(timeout=20.0).clock
            later = clock.next(timeout=10.0, condition=lambda m: m.clock > first).clock
            self.assertGreater(later, first)
            # Stats are stamped with simulated time: close to /clock, far from the epoch.
            m = stats.next(timeout=10.0)
            self.assertLess(abs((m.header.stamp - clock.msg.clock).to_sec()), 1.0)
            self.assertTrue(pause(True).success)
            # /clock messages sent before the pause took effect may still arrive: the frozen
            # time is the one two consecutive messages agree on.
            frozen = clock.settled(key=lambda m: m.clock, timeout=10.0).clock
            time.sleep(0.5)
            self.assertEqual(clock.next(timeout=10.0).clock, frozen)
            self.assertTrue(pause(False).success)
            self.assertGreater(
                clock.next(timeout=10.0, condition=lambda m: m.clock > frozen).clock, frozen)
        finally:
            clock.close()
            stats.close()


if __name__ == '__main__':
    rospy.init_node('test_sim_clock')
    rostest.rosrun('pbf_ros', 'sim_clock', SimClockTest)
