#!/usr/bin/python3
"""pbf_node on another node's /clock is paced by it, as every node's timers are: a simulator
that pauses or slows holds the fluid with it. Until session 41 the fluid was paced by the
wall clock whatever /clock did, so on a stopped clock its stamps ran on ahead of it (and of
the poses a simulator publishes at its time)."""
import threading
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Clock

from fluid_test_util import stats_listener

START = 1000.0  # [s] the clock this test publishes
STEP = 1.0 / 240.0  # [s] the longest time step (fluid_defaults.yaml's max_time_step)


class ControlledClock:
    """Publishes /clock every 10 ms of wall time, at a speed that can change (0: stands)."""

    def __init__(self):
        self._publisher = rospy.Publisher('/clock', Clock, queue_size=10)
        self._lock = threading.Lock()
        self._origin = (START, time.time())  # the clock read this at this wall time
        self._speed = 1.0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run)
        self._thread.start()

    def now(self):
        with self._lock:
            return self._origin[0] + self._speed * (time.time() - self._origin[1])

    def set_speed(self, speed):
        with self._lock:
            wall = time.time()
            self._origin = (self._origin[0] + self._speed * (wall - self._origin[1]), wall)
            self._speed = speed

    def _run(self):
        while not self._stop.is_set():
            self._publisher.publish(Clock(clock=rospy.Time.from_sec(self.now())))
            time.sleep(0.01)

    def close(self):
        self._stop.set()
        self._thread.join()


class ExternalClockTest(unittest.TestCase):

    def test_the_fluid_keeps_step_with_another_nodes_clock(self):
        stats = stats_listener()
        clock = None
        try:
            # No /clock yet: the stats come (on the wall clock), the fluid waits.
            stats.next(timeout=30.0)
            time.sleep(1.0)
            self.assertEqual(stats.next(timeout=5.0).sim_time, 0.0)

            clock = ControlledClock()
            stats.next(timeout=10.0, condition=lambda m: m.sim_time > 0.0)

            def advance(seconds):
                """The fluid's and the clock's advance over `seconds` of wall time, and the
                largest lead of a stamp over the clock in between."""
                first = stats.next(timeout=5.0)
                clock_first = clock.now()
                lead = 0.0
                end = time.time() + seconds
                last = first
                while time.time() < end:
                    last = stats.next(timeout=5.0)
                    lead = max(lead, last.header.stamp.to_sec() - clock.now())
                return last.sim_time - first.sim_time, clock.now() - clock_first, lead

            for speed in (1.0, 0.0, 0.5, 1.0):
                clock.set_speed(speed)
                stats.next(timeout=5.0)  # a message of the new speed's time
                stats.next(timeout=5.0)
                fluid, ticked, lead = advance(2.0)
                # The stats come at 20 Hz: a message may be up to 0.05 s + one step old.
                self.assertLessEqual(fluid, ticked + 0.06 + 2 * STEP,
                                     'clock speed %g: the fluid ran ahead of /clock' % speed)
                self.assertLessEqual(lead, 2 * STEP,
                                     'clock speed %g: stamps ahead of /clock' % speed)
                if speed > 0.0:  # this scene runs far faster than real time on one thread
                    self.assertGreater(fluid, 0.8 * ticked - 0.06,
                                       'clock speed %g: the fluid fell behind /clock' % speed)
                else:
                    self.assertLess(fluid, 2 * STEP, 'the fluid moved while /clock stood')
        finally:
            if clock:
                clock.close()
            stats.close()


if __name__ == '__main__':
    rospy.init_node('test_external_clock', disable_rostime=True)
    rostest.rosrun('pbf_ros', 'external_clock', ExternalClockTest)
