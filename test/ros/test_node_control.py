#!/usr/bin/python3
"""pbf_node's controls: ~reset, ~pause, ~step, dynamic_reconfigure (levels: what resets and
what does not), and refusal of bad requests while the simulation carries on."""
import math
import subprocess
import time
import unittest

import dynamic_reconfigure.client
import roslib.packages
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from std_srvs.srv import SetBool, Trigger

from fluid_test_util import (NODE, SIMULATION, Latest, cloud_listener, cloud_points, mean,
                             stats_listener)


class NodeControlTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        for name in ('reset', 'pause', 'step'):
            rospy.wait_for_service(NODE + '/' + name, timeout=30.0)
        cls.reset = rospy.ServiceProxy(NODE + '/reset', Trigger)
        cls.pause = rospy.ServiceProxy(NODE + '/pause', SetBool)
        cls.step = rospy.ServiceProxy(NODE + '/step', Trigger)
        cls.reconfigure = dynamic_reconfigure.client.Client(NODE, timeout=30.0)
        cls.stats = stats_listener()
        cls.defaults = cls.reconfigure.get_configuration(timeout=10.0)

    def setUp(self):
        # Every test starts from the default scene, running.
        self.reconfigure.update_configuration({
            'scene': 'dam_break', 'gravity_x': 0.0, 'gravity_y': 0.0, 'gravity_z': -9.81,
            'xsph_viscosity': self.defaults['xsph_viscosity']})
        self.assertTrue(self.pause(False).success)

    def _pause_and_reset(self):
        self.assertTrue(self.pause(True).success)
        response = self.reset()
        self.assertTrue(response.success, response.message)

    def test_yaml_values_seed_the_server(self):
        # node_control.test sets xsph_viscosity 0.002 (the scene leaves it at the solver default).
        self.assertAlmostEqual(self.defaults['xsph_viscosity'], 0.002)
        self.assertAlmostEqual(self.defaults['particle_spacing'], 0.05)

    def _paused_positions(self):
        """The (paused) fluid's positions: a state is published once, and again to newcomers."""
        clouds = cloud_listener()
        try:
            return sorted(p[:3] for p in cloud_points(clouds.current_or_next(timeout=10.0)))
        finally:
            clouds.close()

    def test_reset_restores_the_initial_positions(self):
        self._pause_and_reset()
        initial = self._paused_positions()
        self.assertTrue(self.pause(False).success)
        self.stats.next(timeout=10.0, condition=lambda m: m.sim_time > 0.2)
        self.assertTrue(self.pause(True).success)
        moved = self._paused_positions()
        self.assertNotEqual(initial, moved)
        self.assertTrue(self.reset().success)
        restored = self._paused_positions()
        self.assertEqual(initial, restored)
        m = self.stats.next(timeout=10.0, condition=lambda m: m.step_count == 0)
        self.assertEqual(m.sim_time, 0.0)

    def test_a_paused_state_is_published_once_with_its_simulated_stamp(self):
        self._pause_and_reset()
        clouds = cloud_listener()
        try:
            previous = clouds.current_or_next(timeout=10.0).header.stamp
            for _ in range(3):  # ~step: one new state each, stamped dt later
                self.assertTrue(self.step().success)
                previous = clouds.current_or_next(
                    timeout=10.0, condition=lambda m, p=previous: m.header.stamp > p).header.stamp
            count = clouds.count
            rospy.sleep(0.5)  # paused: nothing new to publish
            self.assertEqual(clouds.count, count)
        finally:
            clouds.close()

    def test_pause_freezes_sim_time_and_step_advances_exactly_one(self):
        response = self.pause(True)
        self.assertTrue(response.success, response.message)
        # Stats published before the pause took effect may still arrive: wait until the step
        # counter stands still, not for "the next message".
        first = self.stats.settled(key=lambda m: m.step_count, timeout=10.0)
        self.assertEqual(first.real_time_factor, 0.0)
        time.sleep(0.5)
        later = self.stats.next(timeout=10.0)
        self.assertEqual(first.sim_time, later.sim_time)
        self.assertEqual(first.step_count, later.step_count)
        self.assertEqual(later.real_time_factor, 0.0)
        for _ in range(3):
            before = self.stats.next(timeout=10.0).step_count
            response = self.step()
            self.assertTrue(response.success, response.message)
            # Wait for a condition, not for "the next message" (it may predate the step).
            after = self.stats.next(timeout=10.0, condition=lambda m: m.step_count > before)
            self.assertEqual(after.step_count, before + 1)
            self.assertGreater(after.dt, 0.0)
        response = self.pause(False)
        self.assertTrue(response.success, response.message)
        resumed = self.stats.next(timeout=10.0, condition=lambda m: m.step_count > after.step_count)
        self.assertGreater(resumed.sim_time, after.sim_time)

    def test_step_is_refused_while_running(self):
        response = self.step()
        self.assertFalse(response.success)
        self.assertIn('pause', response.message)

    def test_gravity_changes_the_motion_in_the_direction_asked(self):
        self._pause_and_reset()
        # Sideways gravity, away from the wall the column leans on (x = 0).
        config = self.reconfigure.update_configuration({'gravity_x': 9.81, 'gravity_z': 0.0})
        self.assertAlmostEqual(config['gravity_x'], 9.81)
        clouds = cloud_listener()
        try:
            self.assertTrue(self.pause(False).success)
            self.stats.next(timeout=20.0, condition=lambda m: m.sim_time > 0.15)
            points = cloud_points(clouds.next(timeout=10.0))
        finally:
            clouds.close()
        vx, vy, vz = (mean(p[i] for p in points) for i in (3, 4, 5))
        self.assertGreater(vx, 0.3)
        self.assertGreater(vx, 5 * abs(vz))
        self.assertGreater(vx, 5 * abs(vy))

    def test_viscosity_change_does_not_reset_the_fluid(self):
        before = self.stats.next(timeout=20.0, condition=lambda m: m.step_count > 20)
        config = self.reconfigure.update_configuration({'xsph_viscosity': 0.001})
        self.assertAlmostEqual(config['xsph_viscosity'], 0.001)
        after = self.stats.next(timeout=10.0, condition=lambda m: m.step_count > before.step_count)
        self.assertGreaterEqual(after.step_count, before.step_count)
        self.assertGreaterEqual(after.sim_time, before.sim_time)
        self.assertEqual(after.particle_count, before.particle_count)

    def test_scene_change_resets_the_fluid(self):
        self.reconfigure.update_configuration({'xsph_viscosity': 0.003})
        before = self.stats.next(timeout=20.0, condition=lambda m: m.step_count > 20)
        config = self.reconfigure.update_configuration({'scene': 'hydrostatic_tank'})
        self.assertEqual(config['scene'], 'hydrostatic_tank')
        # What the user set (particle_spacing at start-up, xsph_viscosity live) stays set.
        self.assertAlmostEqual(config['particle_spacing'], 0.05)
        self.assertAlmostEqual(config['xsph_viscosity'], 0.003)
        after = self.stats.next(timeout=10.0,
                                condition=lambda m: m.particle_count != before.particle_count)
        self.assertNotEqual(after.particle_count, before.particle_count)
        self.assertLess(after.step_count, before.step_count)

    def test_spacing_change_rebuilds_the_fluid(self):
        before = self.stats.next(timeout=20.0, condition=lambda m: m.step_count > 20)
        try:
            config = self.reconfigure.update_configuration({'particle_spacing': 0.06})
            self.assertAlmostEqual(config['particle_spacing'], 0.06)
            after = self.stats.next(timeout=10.0,
                                    condition=lambda m: m.particle_count != before.particle_count)
            self.assertLess(after.particle_count, before.particle_count)
            self.assertLess(after.step_count, before.step_count)
        finally:
            self.reconfigure.update_configuration({'particle_spacing': 0.05})

    def test_steps_stopped_at_the_iteration_cap_warn_on_diagnostics(self):
        # A tolerance two corrections cannot reach: every step stops at max_iterations.
        diagnostics = Latest('/diagnostics', DiagnosticArray)
        try:
            self.reconfigure.update_configuration({
                'min_iterations': 2, 'max_iterations': 2, 'density_tolerance': 1e-6})
            capped = lambda s: s.name == SIMULATION and 'stopped at max_iterations (2)' in s.message
            m = diagnostics.next(timeout=20.0, condition=lambda m: any(capped(s) for s in m.status))
            status = [s for s in m.status if capped(s)][0]
            self.assertGreaterEqual(status.level, DiagnosticStatus.WARN)
            values = {kv.key: kv.value for kv in status.values}
            self.assertGreater(int(values['steps at max_iterations since previous report']), 0)
            # Back at the defaults the solve meets its tolerance again: no such warning.
            self.reconfigure.update_configuration({
                'max_iterations': self.defaults['max_iterations'],
                'density_tolerance': self.defaults['density_tolerance']})
            m = diagnostics.next(timeout=20.0, condition=lambda m: any(
                s.name == SIMULATION and 'max_iterations' not in s.message for s in m.status))
            self.assertIsNotNone(m)
        finally:
            self.reconfigure.update_configuration({
                'min_iterations': self.defaults['min_iterations'],
                'max_iterations': self.defaults['max_iterations'],
                'density_tolerance': self.defaults['density_tolerance']})
            diagnostics.close()

    def test_too_many_particles_are_refused(self):
        # dam_break at 5 mm spacing needs 1.28 M particles, over ~max_particles (1 M).
        before = self.stats.next(timeout=10.0)
        config = self.reconfigure.update_configuration({'particle_spacing': 0.005})
        self.assertAlmostEqual(config['particle_spacing'], 0.05)
        after = self.stats.next(timeout=10.0, condition=lambda m: m.step_count > before.step_count)
        self.assertEqual(after.particle_count, before.particle_count)

    def test_unknown_scene_is_refused_and_the_scene_keeps_running(self):
        before = self.stats.next(timeout=10.0)
        config = self.reconfigure.update_configuration({'scene': 'no_such_scene'})
        self.assertEqual(config['scene'], 'dam_break')
        after = self.stats.next(timeout=10.0, condition=lambda m: m.step_count > before.step_count)
        self.assertEqual(after.particle_count, before.particle_count)
        self.assertGreater(after.sim_time, before.sim_time)

    def test_non_finite_values_are_refused_and_out_of_range_clamped(self):
        config = self.reconfigure.update_configuration({'xsph_viscosity': float('nan')})
        self.assertTrue(math.isfinite(config['xsph_viscosity']))
        self.assertAlmostEqual(config['xsph_viscosity'], self.defaults['xsph_viscosity'])
        config = self.reconfigure.update_configuration({'gravity_z': -1.0e9})
        self.assertEqual(config['gravity_z'], -100.0)
        # dynamic_reconfigure's server clamps infinities to the range before the node sees
        # them; NaN is what reaches the node, and the node refuses it (above).
        config = self.reconfigure.update_configuration({'gravity_z': float('inf')})
        self.assertEqual(config['gravity_z'], 100.0)
        # The simulation carries on, finite: steps beyond the last one seen.
        seen = self.stats.current_or_next(timeout=10.0).step_count
        after = self.stats.next(timeout=10.0, condition=lambda m: m.step_count > seen)
        self.assertTrue(math.isfinite(after.max_speed))

    def test_bad_scene_at_startup_exits_non_zero_naming_it(self):
        node = roslib.packages.find_node('pbf_ros', 'pbf_node')
        self.assertTrue(node, 'pbf_node executable not found')
        result = subprocess.run(
            [node[0], '__name:=bad_scene_fluid', '_scene:=no_such_scene',
             '_diagnostics/capped_steps_warn_fraction:=-0.5'],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=30, text=True)
        self.assertNotEqual(result.returncode, 0)
        self.assertIn('no_such_scene', result.stdout)
        # Node settings are read first: a bad one is named before the scene fails.
        self.assertIn('capped_steps_warn_fraction -0.5 is not in [0, 1]', result.stdout)


if __name__ == '__main__':
    rospy.init_node('test_node_control')
    rostest.rosrun('pbf_ros', 'node_control', NodeControlTest)
