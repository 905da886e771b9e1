#!/usr/bin/python3
"""pbf_ros/FluidNodelet in a nodelet manager (fluid_nodelet.test): the fluid's topics are
published by the manager process, cloud and stats arrive, /diagnostics name the nodelet (not
the manager), and depth_image_proc/point_cloud_xyzrgb, loaded into the same manager in the
fluid's namespace without remaps, turns the rgb/ and depth_registered/ images into a
coloured point cloud of the fluid surface."""
import math
import struct
import time
import unittest

import rosgraph
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import PointCloud2

from fluid_test_util import NODE, SIMULATION, Latest, cloud_listener, stats_listener

MANAGER = '/fluid_manager'


def publishers_of(topic):
    publishers, _, _ = rosgraph.Master('/test_fluid_nodelet').getSystemState()
    return sorted(nodes for name, nodes in publishers if name == topic)


class FluidNodeletTest(unittest.TestCase):

    def test_01_the_manager_publishes_the_fluid(self):
        topics = [NODE + t for t in ('/particles', '/stats', '/rgb/image_rect_color',
                                     '/depth_registered/image_rect')]
        deadline = time.time() + 30.0
        while not all(publishers_of(t) for t in topics) and time.time() < deadline:
            time.sleep(0.2)
        for topic in topics:
            self.assertEqual(publishers_of(topic), [[MANAGER]], topic)

    def test_02_cloud_and_stats_arrive(self):
        stats = stats_listener()
        clouds = cloud_listener()
        try:
            cloud = clouds.next(timeout=30.0)
            self.assertEqual(cloud.header.frame_id, 'fluid_domain')
            m = stats.next(timeout=10.0, condition=lambda m: 'cloud' not in m.skipped_stages)
            self.assertEqual(cloud.width * cloud.height, m.particle_count)
            self.assertGreater(m.particle_count, 100)  # particle_spacing 0.05: ~1.3k
            later = stats.next(timeout=10.0, condition=lambda l: l.step_count > m.step_count)
            self.assertGreater(later.sim_time, m.sim_time)  # it keeps stepping
        finally:
            stats.close()
            clouds.close()

    def test_03_diagnostics_are_named_after_the_nodelet(self):
        diagnostics = Latest('/diagnostics', DiagnosticArray)
        try:
            m = diagnostics.next(timeout=15.0, condition=lambda m: any(
                s.name == SIMULATION for s in m.status))
            names = [s.name for s in m.status]
            self.assertFalse(any(n.startswith(MANAGER[1:] + ':') for n in names), names)
        finally:
            diagnostics.close()

    def test_04_depth_image_proc_makes_a_coloured_cloud_of_the_surface(self):
        points = Latest(NODE + '/depth_registered/points', PointCloud2)
        try:
            cloud = points.next(timeout=45.0)
        finally:
            points.close()
        self.assertEqual(cloud.header.frame_id, 'fluid_camera_optical')
        self.assertEqual((cloud.width, cloud.height), (160, 120))
        offsets = {f.name: f.offset for f in cloud.fields}
        self.assertTrue({'x', 'y', 'z', 'rgb'} <= set(offsets), offsets)
        finite, colours = 0, set()
        for i in range(cloud.width * cloud.height):
            base = i * cloud.point_step
            z = struct.unpack_from('<f', cloud.data, base + offsets['z'])[0]
            if math.isfinite(z):
                finite += 1
                self.assertTrue(0.02 < z < 20.0, z)  # metres in front of the camera
                colours.add(struct.unpack_from('<I', cloud.data, base + offsets['rgb'])[0])
        self.assertGreater(finite, 50, 'fluid pixels became points')
        self.assertLess(finite, cloud.width * cloud.height, 'background pixels did not')
        self.assertGreater(len(colours), 1, 'points carry the shaded colour')


if __name__ == '__main__':
    rospy.init_node('test_fluid_nodelet')
    rostest.rosrun('pbf_ros', 'fluid_nodelet', FluidNodeletTest)
