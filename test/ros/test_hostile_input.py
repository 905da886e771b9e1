#!/usr/bin/python3
"""Live hostile input (issue 11): every failed scene change is a named refusal after which
the reconfigure server reports the scene that runs; a spacing asking for millions of
particles is refused before anything is allocated, a negative one by name; Fluid.cfg's
range ends are usable;
non-finite start-up values fall back to Fluid.cfg's defaults."""
import math
import os
import tempfile
import unittest
import xmlrpc.client

import dynamic_reconfigure.client
import rosgraph
import rospy
import rostest
import tf2_ros

from diagnostic_msgs.msg import DiagnosticArray
from fluid_test_util import NODE, SIMULATION, Latest, stats_listener


def peak_rss_mb(node_name):
    """The node process's peak resident memory (VmHWM) [MB]."""
    api = rosgraph.Master('/test_hostile_input').lookupNode(node_name)
    pid = xmlrpc.client.ServerProxy(api).getPid('/test_hostile_input')[2]
    with open('/proc/%d/status' % pid) as f:
        for line in f:
            if line.startswith('VmHWM:'):
                return int(line.split()[1]) / 1024.0
    raise AssertionError('no VmHWM for pid %d' % pid)


def scene_file(text):
    f = tempfile.NamedTemporaryFile('w', suffix='.yaml', delete=False)
    f.write(text)
    f.close()
    return f.name


class HostileInputTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.client = dynamic_reconfigure.client.Client(NODE, timeout=30.0)
        cls.stats = stats_listener()
        cls.running = cls.client.get_configuration(timeout=10.0)['scene']

    def assert_still_running(self, particle_count):
        """The running scene is what the server reports, and it keeps stepping."""
        self.assertEqual(self.client.get_configuration(timeout=10.0)['scene'], self.running)
        # Steps beyond the last one seen (not "the next message", which may predate the call).
        seen = self.stats.current_or_next(timeout=20.0).step_count
        later = self.stats.next(timeout=20.0, condition=lambda m: m.step_count > seen)
        self.assertEqual(later.particle_count, particle_count)

    def test_scenes_that_fail_are_refused_and_the_server_shows_the_running_one(self):
        count = self.stats.next(timeout=20.0).particle_count
        body = 'container: {min: [0,0,0], max: [1,1,1]}\nfluid: [{box: {min: [0,0,0], max: [1,1,0.5]}}]\n'
        bad = [scene_file('name: [a, b]\n' + body),
               scene_file(body + '? [a, b]\n: 1\n'),
               scene_file(body + 'obstacles: [{box: {center: [0.5,0.5,0.5], half_extents: [1,1,1]}}]\n'),
               tempfile.gettempdir(), '/dev/zero']
        try:
            for scene in bad:
                config = self.client.update_configuration({'scene': scene})
                self.assertEqual(config['scene'], self.running, scene)
                # A later, unrelated change does not re-try the bad scene.
                config = self.client.update_configuration({'xsph_viscosity': 0.002})
                self.assertEqual(config['scene'], self.running, scene)
                self.assertAlmostEqual(config['xsph_viscosity'], 0.002)
                self.assert_still_running(count)
        finally:
            for path in bad[:3]:
                os.unlink(path)

    def test_a_spacing_bomb_is_refused_with_memory_flat(self):
        count = self.stats.next(timeout=20.0).particle_count
        before = peak_rss_mb(NODE)
        # 0.01 m in a 4 x 4 x 0.4 m layer: 6.4 million particles (~150 MB before they were
        # counted first), against ~max_particles 20 000.
        config = self.client.update_configuration({'particle_spacing': 0.01})
        self.assertAlmostEqual(config['particle_spacing'], 0.2)
        self.assertLess(peak_rss_mb(NODE) - before, 50.0)
        self.assert_still_running(count)

    def test_a_negative_spacing_is_refused_as_not_positive(self):
        # The reconfigure server clamps a request to Fluid.cfg's range before the node sees
        # it. With a range from 0.005 m, -1 arrived as 0.005 and rebuilt a fluid with the
        # finest spacing (384 000 particles in a probe's tank); here it would have been refused
        # for its particle count, for the wrong reason. The range now starts at 0: the node
        # refuses the spacing itself, by name.
        count = self.stats.next(timeout=20.0).particle_count
        diagnostics = Latest('/diagnostics', DiagnosticArray)
        try:
            config = self.client.update_configuration({'particle_spacing': -1.0})
            self.assertAlmostEqual(config['particle_spacing'], 0.2)
            refused = lambda s: s.name == SIMULATION and any(
                kv.key == 'last refused request' and 'particle_spacing must be a finite number > 0'
                in kv.value for kv in s.values)
            self.assertIsNotNone(diagnostics.next(
                timeout=20.0, condition=lambda m: any(refused(s) for s in m.status)))
        finally:
            diagnostics.close()
        self.assert_still_running(count)

    def test_non_finite_start_up_values_fall_back_to_the_defaults(self):
        # hostile_input.test starts the node with camera_position_x NaN and render_vfov inf.
        # Refused, they were "kept": the camera's tf went out with NaN in it.
        config = self.client.get_configuration(timeout=10.0)
        defaults = {d['name']: d['default']
                    for d in self.client.get_parameter_descriptions(timeout=10.0)}
        for name in ('camera_position_x', 'render_vfov'):
            self.assertTrue(math.isfinite(config[name]), '%s = %r' % (name, config[name]))
            self.assertEqual(config[name], defaults[name], name)
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        t = buffer.lookup_transform('fluid_domain', 'fluid_camera_optical', rospy.Time(0),
                                    rospy.Duration(10.0)).transform
        values = [t.translation.x, t.translation.y, t.translation.z,
                  t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w]
        self.assertTrue(all(math.isfinite(v) for v in values), values)

    def test_the_advertised_minimum_of_scorr_delta_q_is_usable(self):
        minimum = self.client.get_parameter_descriptions(timeout=10.0)
        minimum = [d for d in minimum if d['name'] == 'scorr_delta_q'][0]['min']
        config = self.client.update_configuration({'scorr_delta_q': minimum})
        self.assertAlmostEqual(config['scorr_delta_q'], minimum)
        config = self.client.update_configuration({'scorr_delta_q': 0.2})
        self.assertAlmostEqual(config['scorr_delta_q'], 0.2)


if __name__ == '__main__':
    rospy.init_node('test_hostile_input')
    rostest.rosrun('pbf_ros', 'hostile_input', HostileInputTest)
