#!/usr/bin/python3
"""Without a usable GL back-end pbf_node keeps simulating: /diagnostics say the surface is
unavailable (WARN), ~stats report no surface work even with a subscriber."""
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from sensor_msgs.msg import Image

from fluid_test_util import NODE, SIMULATION, Latest, stats_listener


class SurfaceWithoutGlTest(unittest.TestCase):

    def test_simulation_runs_on_and_diagnostics_say_why_there_is_no_surface(self):
        image = Latest(NODE + '/rgb/image_rect_color', Image)
        stats = stats_listener()
        diagnostics = Latest('/diagnostics', DiagnosticArray)
        try:
            first = stats.next(timeout=30.0)
            time.sleep(2.0)
            last = stats.next(timeout=10.0)
            self.assertGreater(last.step_count, first.step_count)
            self.assertIn('surface', last.skipped_stages)
            self.assertEqual(last.surface_frames, 0)
            self.assertEqual(image.count, 0)
            m = diagnostics.next(timeout=15.0, condition=lambda m: any(
                s.name == SIMULATION for s in m.status))
            status = [s for s in m.status if s.name == SIMULATION][0]
            values = {kv.key: kv.value for kv in status.values}
            self.assertTrue(values['surface rendering'].startswith('unavailable'), values)
            self.assertGreaterEqual(status.level, DiagnosticStatus.WARN)
        finally:
            image.close()
            stats.close()
            diagnostics.close()


if __name__ == '__main__':
    rospy.init_node('test_surface_no_gl')
    rostest.rosrun('pbf_ros', 'surface_no_gl', SurfaceWithoutGlTest)
