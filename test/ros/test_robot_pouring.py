#!/usr/bin/python3
"""The robot pouring demo (issue 12, part 5) headless: the tap fills the arm's cup with 0.2 l,
the arm holds it still, carries it over the basin and pours. Checks that the water's vertical
force on the cup (~wrench/cup) matches the weight of the water in it within 10 % while it is
held still, that the ball floats, that the particle count follows the tap and the drain
(the books of ~stats balance in every message; the tap gives its volume, the drain takes),
and that after ~reset the arm starts over with the fluid and the cup fills again."""
import math
import threading
import unittest

import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import WrenchStamped
from std_srvs.srv import SetBool, Trigger

from fluid_test_util import NODE, Latest, cloud_listener, cloud_points, stats_listener

HOLD = (1.5, 2.2)          # [s] the full cup is held still under the closed tap
POURED = 5.0               # [s] the arm has tipped the cup and held it tipped for a second
CUP_RADIUS, CUP_BOTTOM, CUP_TOP = 0.05, 0.03, 0.12  # in the cup link's frame (on its stem)
G = 9.81


class Recorder:
    """Keeps every message of a topic (with a lock)."""

    def __init__(self, topic, msg_type):
        self.lock = threading.Lock()
        self.msgs = []
        self.sub = rospy.Subscriber(topic, msg_type, self._add, queue_size=100)

    def _add(self, msg):
        with self.lock:
            self.msgs.append(msg)

    def all(self):
        with self.lock:
            return list(self.msgs)


class RobotPouringTest(unittest.TestCase):

    def test_pour(self):
        stats = stats_listener()
        all_stats = Recorder(NODE + '/stats', type(stats.next(timeout=60.0)))
        wrenches = Recorder(NODE + '/wrench/cup', WrenchStamped)
        buffer = tf2_ros.Buffer(cache_time=rospy.Duration(60.0))
        tf2_ros.TransformListener(buffer)
        rospy.wait_for_service(NODE + '/pause', timeout=30.0)
        self.assertTrue(rospy.ServiceProxy(NODE + '/pause', SetBool)(False).success)

        # The full cup, held still: the water in it (from the cloud, in the cup's frame).
        clouds = cloud_listener()
        try:
            cloud = clouds.next(timeout=60.0, condition=lambda c: c.header.stamp.to_sec() > 2.0)
        finally:
            clouds.close()
        held = self.in_cup(buffer, cloud)
        mass = stats.next(timeout=10.0).particle_mass
        weight = held * mass * G
        rospy.loginfo('at %.2f s the cup holds %d particles: %.4f N of water',
                      cloud.header.stamp.to_sec(), held, weight)
        self.assertGreater(held, 80)  # most of the tap's 102 particles went into the cup

        # Wait for the pour; then look back at the hold.
        end = stats.next(timeout=60.0, condition=lambda m: m.sim_time > POURED)
        held_forces = [w.wrench.force.z for w in wrenches.all()
                       if HOLD[0] <= w.header.stamp.to_sec() <= HOLD[1]]
        self.assertGreater(len(held_forces), 5)
        self.assertTrue(all(w.header.frame_id == 'cup' for w in wrenches.all()))
        force = -sum(held_forces) / len(held_forces)  # the water pushes the cup down
        rospy.loginfo('held still: water pushes the cup down with %.4f N (%d messages), its '
                      'weight is %.4f N: %+.1f %%', force, len(held_forces), weight,
                      100.0 * (force - weight) / weight)
        self.assertAlmostEqual(force, weight, delta=0.1 * weight)

        # The books balance in every message; the tap gave its 0.2 l, the drain took some.
        messages = all_stats.all()
        for m in messages:
            self.assertEqual(m.particle_count,
                             m.initial_particle_count + m.particles_emitted - m.particles_drained)
        self.assertEqual(end.particles_emitted, round(0.0002 / 0.0125 ** 3))
        self.assertGreater(end.particles_drained, 0)
        filling = [m for m in messages if m.sim_time < 0.3]
        self.assertTrue(filling and all(m.particles_emitted == 0 for m in filling))
        rospy.loginfo('at %.2f s: %d particles = %d + %d emitted - %d drained', end.sim_time,
                      end.particle_count, end.initial_particle_count, end.particles_emitted,
                      end.particles_drained)

        # Poured: the cup is (nearly) empty; the ball floats at the water line.
        clouds = cloud_listener()
        try:
            cloud = clouds.next(timeout=30.0)
        finally:
            clouds.close()
        left = self.in_cup(buffer, cloud)
        rospy.loginfo('after the pour the cup holds %d particles', left)
        self.assertLess(left, 0.1 * held)
        ball = buffer.lookup_transform('fluid_domain', 'ball', rospy.Time(0), rospy.Duration(5.0))
        z = ball.transform.translation.z
        rospy.loginfo('ball centre at z = %.4f m', z)
        self.assertGreater(z, 0.03 + 0.01)   # off the floor (radius 3 cm)
        self.assertLess(z, 0.06 + 0.02)      # not above the water (0.06 m at the start)

        # ~reset starts the fluid's time again (not /clock's): the arm starts over with it,
        # so the tap fills the upright cup again instead of pouring past the tipped one.
        reset = rospy.ServiceProxy(NODE + '/reset', Trigger)
        answer = reset()
        self.assertTrue(answer.success, answer.message)
        # Subscribed now, not at 2 s: the cup tips from 3 s, and a connection made that late
        # on a loaded machine could bring its first cloud after the cup has poured.
        clouds = cloud_listener()
        try:
            again = stats.next(timeout=60.0, condition=lambda m: m.sim_time > 2.0 and
                               m.header.stamp.to_sec() > end.header.stamp.to_sec() + 2.0)
            cloud = clouds.current_or_next(
                timeout=30.0, condition=lambda c: c.header.stamp >= again.header.stamp)
        finally:
            clouds.close()
        refilled = self.in_cup(buffer, cloud)
        rospy.loginfo('after ~reset, at %.2f s of fluid time the cup holds %d particles',
                      again.sim_time, refilled)
        self.assertGreater(refilled, 80)
        stats.close()

    @staticmethod
    def in_cup(buffer, cloud):
        """Particles of the cloud inside the cup's cylinder (its link frame, z up)."""
        t = buffer.lookup_transform('cup', 'fluid_domain', cloud.header.stamp, rospy.Duration(5.0))
        q = t.transform.rotation
        p = t.transform.translation

        def to_cup(x, y, z):  # rotate by q, then translate
            ux, uy, uz = q.x, q.y, q.z
            tx = 2 * (uy * z - uz * y)
            ty = 2 * (uz * x - ux * z)
            tz = 2 * (ux * y - uy * x)
            return (x + q.w * tx + uy * tz - uz * ty + p.x,
                    y + q.w * ty + uz * tx - ux * tz + p.y,
                    z + q.w * tz + ux * ty - uy * tx + p.z)

        count = 0
        for point in cloud_points(cloud):
            x, y, z = to_cup(*point[:3])
            if math.hypot(x, y) < CUP_RADIUS and CUP_BOTTOM < z < CUP_TOP:
                count += 1
        return count


if __name__ == '__main__':
    rospy.init_node('test_robot_pouring')
    rostest.rosrun('pbf_ros', 'robot_pouring', RobotPouringTest)
