#!/usr/bin/python3
"""pbf_node on another node's /clock that starts after it: the stamps' anchor, taken while ROS
time was still 0, is taken again once the clock comes (they counted from 0: a probe's stats
were stamped 1-7 s while /clock said 1e9). And it is taken again when that clock jumps back
(a bag that loops) or far ahead (a probe's stamps stayed near 500 s while /clock said 1e9)."""
import threading
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Clock

from fluid_test_util import stats_listener

START = 1000.0  # [s] the clock this test publishes, at wall speed


class LateClockTest(unittest.TestCase):

    def test_stamps_follow_a_clock_that_starts_after_the_node(self):
        stats = stats_listener()
        try:
            first = stats.next(timeout=30.0)  # the node runs on ROS time 0
            self.assertLess(first.header.stamp.to_sec(), START / 2)
            publisher = rospy.Publisher('/clock', Clock, queue_size=10)
            stop = threading.Event()
            lock = threading.Lock()
            origin = {'clock': START, 'wall': time.time()}  # the clock reads 'clock' at 'wall'

            def publish():
                while not stop.is_set():
                    with lock:
                        now = origin['clock'] + time.time() - origin['wall']
                    publisher.publish(Clock(clock=rospy.Time.from_sec(now)))
                    time.sleep(0.01)

            clock = threading.Thread(target=publish)
            clock.start()
            try:
                m = stats.next(timeout=20.0, condition=lambda m: m.header.stamp.to_sec() > START / 2)
                # Within a few seconds of the clock (the node runs at most at real time here).
                self.assertLess(abs(m.header.stamp.to_sec() - START), 10.0)
                for jumped in (START / 2, 1e9):  # back (a bag that loops), then far ahead
                    with lock:
                        origin['clock'], origin['wall'] = jumped, time.time()
                    m = stats.next(timeout=20.0,
                                   condition=lambda m, j=jumped: abs(m.header.stamp.to_sec() - j) < 10.0)
                    self.assertLess(abs(m.header.stamp.to_sec() - jumped), 10.0)
            finally:
                stop.set()
                clock.join()
        finally:
            stats.close()


if __name__ == '__main__':
    rospy.init_node('test_late_clock', disable_rostime=True)
    rostest.rosrun('pbf_ros', 'late_clock', LateClockTest)
