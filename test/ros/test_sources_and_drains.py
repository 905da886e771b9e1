#!/usr/bin/python3
"""Sources and drains in pbf_node (issue 12, part 4), tap_and_drain test scene: the tap's
water and the drain show in ~stats, whose books balance to the particle in every message;
~emit adds a block (exactly `added` particles, fresh lattice sites only) and refuses bad
requests with a message naming what was wrong while the simulation stays as it was."""
import math
import unittest

import rospy
import rostest
from geometry_msgs.msg import Point, Vector3
from pbf_ros.srv import Emit, EmitRequest
from std_srvs.srv import SetBool

from fluid_test_util import NODE, cloud_ids, cloud_listener, cloud_points, stats_listener


def box_request(lo, hi, velocity=(0.0, 0.0, 0.0), frame_id=''):
    return EmitRequest(shape='box', frame_id=frame_id, min=Point(*lo), max=Point(*hi),
                       velocity=Vector3(*velocity))


class SourcesAndDrainsTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        rospy.wait_for_service(NODE + '/emit', timeout=30.0)
        cls.emit = rospy.ServiceProxy(NODE + '/emit', Emit)
        cls.pause = rospy.ServiceProxy(NODE + '/pause', SetBool)
        cls.stats = stats_listener()

    def assert_balanced(self, m):
        self.assertEqual(m.particle_count,
                         m.initial_particle_count + m.particles_emitted - m.particles_drained)
        self.assertAlmostEqual(m.fluid_mass, m.particle_count * m.particle_mass, places=9)

    def test_1_tap_and_drain_balance_in_every_stats_message(self):
        self.assertTrue(self.pause(False).success)
        seen = []
        deadline = rospy.get_time() + 40.0
        while rospy.get_time() < deadline:
            m = self.stats.next(timeout=10.0)
            self.assert_balanced(m)
            seen.append(m)
            if m.particles_emitted > 100 and m.particles_drained > 20:
                break
        last = seen[-1]
        rospy.loginfo('after %.2f s: %d particles = %d + %d emitted - %d drained',
                      last.sim_time, last.particle_count, last.initial_particle_count,
                      last.particles_emitted, last.particles_drained)
        self.assertEqual(last.initial_particle_count, 14 * 10 * 3)
        self.assertGreater(last.particles_emitted, 100)
        self.assertGreater(last.particles_drained, 20)
        # A 3 cm nozzle at d = 0.03 holds 5 sites; a layer every d / v = 30 ms at most.
        self.assertLessEqual(last.particles_emitted, 5 * (1.0 * last.sim_time / 0.03 + 1))
        # The jet starts at the tap's speed: nothing moves faster than its fall from the tap
        # (sqrt(1 + 2 g 0.3) = 2.6 m/s) allows.
        self.assertLess(max(m.max_speed for m in seen), 3.0)

    def test_2_emit_adds_exactly_what_it_says_and_refusals_change_nothing(self):
        self.assertTrue(self.pause(True).success)
        before = self.stats.settled(key=lambda m: m.step_count, timeout=10.0)
        self.assert_balanced(before)

        def refused(request, words):
            response = self.emit(request)
            self.assertFalse(response.success, response.message)
            self.assertEqual(response.added, 0)
            self.assertEqual(response.particle_count, before.particle_count, response.message)
            for word in words:
                self.assertIn(word, response.message)
            return response

        refused(EmitRequest(shape='cube'), ['shape'])
        refused(box_request((0.1, 0.1, float('nan')), (0.2, 0.2, 0.3)), ["'min'"])
        refused(box_request((0.1, 0.1, 0.2), (0.2, 0.2, float('inf'))), ["'max'"])
        refused(box_request((0.2, 0.1, 0.2), (0.1, 0.2, 0.3)), ['min < max'])
        refused(box_request((0.2, 0.1, 0.2), (0.3, 0.2, 0.3), velocity=(1e39, 0, 0)), ["'velocity'"])
        refused(EmitRequest(shape='sphere', center=Point(0.2, 0.15, 0.3), radius=0.0), ["'radius'"])
        refused(box_request((0.0, 0.0, 0.0), (0.42, 0.3, 0.45)), ['~max_particles (1500)'])
        refused(box_request((5.0, 5.0, 5.0), (5.1, 5.1, 5.1)), ['no free lattice site', 'outside'])
        refused(box_request((0.2, 0.1, 0.2), (0.3, 0.2, 0.3), frame_id='no_such_frame'),
                ["'frame_id'", 'no_such_frame'])
        # Echoed text is cut: a 1 MB shape came back as a 1 MB reply (and log line).
        response = refused(EmitRequest(shape='x' * 1000000), ['shape', '(1000000 characters)'])
        self.assertLess(len(response.message), 1000)
        response = refused(box_request((0.2, 0.1, 0.2), (0.3, 0.2, 0.3), frame_id='f' * 100000),
                           ["'frame_id'", '(100000 characters)'])
        self.assertLess(len(response.message), 1000)

        # A 12 x 12 x 12 cm block above the pool: 4 x 4 x 4 sites, all free.
        response = self.emit(box_request((0.21, 0.09, 0.27), (0.33, 0.21, 0.39)))
        self.assertTrue(response.success, response.message)
        self.assertEqual(response.added, 64, response.message)
        self.assertEqual(response.particle_count, before.particle_count + 64)
        after = self.stats.next(timeout=10.0, condition=lambda m: m.particle_count != before.particle_count)
        self.assert_balanced(after)
        self.assertEqual(after.particle_count, before.particle_count + 64)
        self.assertEqual(after.particles_emitted, before.particles_emitted + 64)
        self.assertEqual(after.step_count, before.step_count)  # paused: added between steps

        # The same block again: every site is taken now.
        refused_again = self.emit(box_request((0.21, 0.09, 0.27), (0.33, 0.21, 0.39)))
        self.assertFalse(refused_again.success)
        self.assertIn('occupied', refused_again.message)

        # No particle of the paused cloud sits on another: the block went only where free.
        clouds = cloud_listener()
        try:
            cloud = clouds.current_or_next(timeout=10.0)  # sent once, maybe before the wait
        finally:
            clouds.close()
        points = [p[:3] for p in cloud_points(cloud)]
        ids = cloud_ids(cloud)
        self.assertEqual(len(points), after.particle_count)
        # Ids are unique, and the block's are fresh: above every id the scene started with.
        self.assertEqual(len(set(ids)), len(ids))
        inside = [i for i, p in enumerate(points)
                  if 0.21 < p[0] < 0.33 and 0.09 < p[1] < 0.21 and p[2] > 0.27]
        self.assertEqual(len(inside), 64)
        self.assertTrue(all(ids[i] >= after.initial_particle_count for i in inside))
        block = [points[i] for i in inside]
        for p in block:
            for q in points:
                if q is not p:
                    self.assertGreater(math.dist(p, q), 0.9 * 0.03 - 1e-6)

        # Running again, the block falls into the pool without a burst; the books still balance.
        self.assertTrue(self.pause(False).success)
        m = self.stats.next(timeout=20.0, condition=lambda m: m.sim_time > after.sim_time + 0.5)
        self.assert_balanced(m)


if __name__ == '__main__':
    rospy.init_node('test_sources_and_drains')
    rostest.rosrun('pbf_ros', 'sources_and_drains', SourcesAndDrainsTest)
