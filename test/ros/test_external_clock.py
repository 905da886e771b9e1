#!/usr/bin/python3
"""pbf_node on another node's /clock is paced by it, as every node's timers are: a simulator
that pauses or slows holds the fluid with it. Until session 41 the fluid was paced by the
wall clock whatever /clock did, so on a stopped clock its stamps ran on ahead of it (and of
the poses a simulator publishes at its time). Then a probe found the first version of it
spinning a core while the clock stood after a restart of the pacing, keeping up with a
clock that ticks 0.2 s at a time at 0.02 of its speed, and stamping 13 s ahead of a clock
restarted near 0; each has a phase below."""
import os
import threading
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Clock
from std_srvs.srv import SetBool

from fluid_test_util import node_pid, stats_listener

START = 1000.0  # [s] the clock this test publishes
STEP = 1.0 / 240.0  # [s] the longest time step (fluid_defaults.yaml's max_time_step)


class ControlledClock:
    """Publishes its reading on /clock every `tick` of wall time (10 ms; longer: a coarse
    clock), running at a speed that can change (0: it stands)."""

    def __init__(self):
        self._publisher = rospy.Publisher('/clock', Clock, queue_size=10)
        self._lock = threading.Lock()
        self._origin = (START, time.time())  # the clock read this at this wall time
        self._speed = 1.0
        self.tick = 0.01  # [wall s]
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

    def set_time(self, clock):
        with self._lock:
            self._origin = (clock, time.time())

    def _run(self):
        while not self._stop.is_set():
            self._publisher.publish(Clock(clock=rospy.Time.from_sec(self.now())))
            time.sleep(self.tick)

    def close(self):
        self._stop.set()
        self._thread.join()


def node_cpu_seconds():
    """CPU time [s] pbf_node (named fluid) has used so far, from /proc."""
    with open('/proc/%d/stat' % node_pid()) as f:
        fields = f.read().rsplit(')', 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK')


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

            # The clock stands and the pacing starts again (a resume; likewise a reset, a new
            # real_time_factor, a clock that arrives standing): the node waits, it does not
            # spin (the first version did, at 100 % of a core, until the clock moved).
            clock.set_speed(0.0)
            time.sleep(0.5)  # the node has the clock's last reading
            pause = rospy.ServiceProxy('/fluid/pause', SetBool)
            pause(True)
            pause(False)
            cpu = node_cpu_seconds()
            time.sleep(2.0)
            print('cpu while standing: %.3f s' % (node_cpu_seconds() - cpu))
            self.assertLess(node_cpu_seconds() - cpu, 0.6, 'the node spun while /clock stood')

            # A clock that ticks 0.25 s at a time at its speed 1 (a bag played fast, a coarse
            # simulator): this scene keeps up with it.
            clock.tick = 0.25
            clock.set_speed(1.0)
            fluid, ticked, _ = advance(4.0)
            self.assertGreater(fluid, 0.8 * ticked - 0.3, 'the fluid fell behind a coarse /clock')
            clock.tick = 0.01

            # The clock restarts near 0 (a simulator's reset) after the fluid has simulated more
            # than that: the stamps follow it, not sim_time ahead of it.
            clock.set_time(1.0)
            stats.next(timeout=5.0, condition=lambda m: m.header.stamp.to_sec() < START / 2)
            _, _, lead = advance(1.0)
            self.assertLessEqual(lead, 2 * STEP, 'stamps ahead of a clock restarted near 0')

            # A leap ahead: the fluid simulates at most a tick's worth of it (1 s) to catch up,
            # and its stamps reach the clock's only once that is done (right after this leap
            # they led the clock by up to 0.8 s in the version before).
            clock.set_time(clock.now() + 5.0)
            _, _, lead = advance(1.0)
            self.assertLessEqual(lead, 2 * STEP, 'stamps ahead of a clock that leapt ahead')
        finally:
            if clock:
                clock.close()
            stats.close()


if __name__ == '__main__':
    rospy.init_node('test_external_clock', disable_rostime=True)
    rostest.rosrun('pbf_ros', 'external_clock', ExternalClockTest)
