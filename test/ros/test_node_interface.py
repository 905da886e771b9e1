#!/usr/bin/python3
"""pbf_node's ROS interface: topics and their types, the cloud layout, lazy cloud building,
latched container markers, the static transform and /diagnostics (health, the rate of the
cloud against ~publish_rate, the updater's ~diagnostic_period)."""
import math
import threading
import time
import unittest

import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray, DiagnosticStatus
from sensor_msgs.msg import PointField
from tf2_msgs.msg import TFMessage

from fluid_test_util import (NODE, SIMULATION, Latest, cloud_ids, cloud_listener, cloud_points,
                             stats_listener)

PUBLISH_RATE = 10.0  # node_interface.test's ~publish_rate
EXPECTED_TYPES = {
    NODE + '/particles': 'sensor_msgs/PointCloud2',
    NODE + '/stats': 'pbf_ros/SimulationStats',
    NODE + '/markers': 'visualization_msgs/MarkerArray',
    '/diagnostics': 'diagnostic_msgs/DiagnosticArray',
    '/tf_static': 'tf2_msgs/TFMessage',
}


class NodeInterfaceTest(unittest.TestCase):

    def test_01_topics_are_advertised_with_their_types(self):
        deadline = time.time() + 20.0
        while True:
            topics = dict(rospy.get_published_topics())
            missing = {t: ty for t, ty in EXPECTED_TYPES.items() if topics.get(t) != ty}
            if not missing or time.time() > deadline:
                break
            time.sleep(0.2)
        self.assertEqual(missing, {}, 'advertised: %s' % topics)

    def test_02_no_subscriber_means_no_cloud_work(self):
        stats = stats_listener()
        try:
            for _ in range(3):
                m = stats.next(timeout=20.0)
                self.assertIn('cloud', m.skipped_stages)
                self.assertEqual(m.time_cloud_ms, 0.0)
        finally:
            stats.close()

    def test_03_cloud_layout_and_size(self):
        cloud_sub = cloud_listener()
        stats = stats_listener()
        try:
            cloud = cloud_sub.next(timeout=20.0)
            self.assertEqual(cloud.header.frame_id, 'fluid_domain')
            self.assertEqual([f.name for f in cloud.fields],
                             ['x', 'y', 'z', 'vx', 'vy', 'vz', 'density', 'speed', 'id'])
            for f in cloud.fields:
                self.assertEqual(f.datatype, PointField.UINT32 if f.name == 'id' else PointField.FLOAT32,
                                 f.name)
            # Once someone listens, the stats show the cloud being built.
            m = stats.next(timeout=10.0, condition=lambda m: 'cloud' not in m.skipped_stages)
            self.assertGreater(m.time_cloud_ms, 0.0)
            self.assertEqual(cloud.width * cloud.height, m.particle_count)
            self.assertGreater(m.particle_count, 100)
            points = cloud_points(cloud)
            self.assertTrue(all(math.isfinite(v) for p in points for v in p))
            # Every particle has its own id (a fixed fluid: ids 0 .. n-1, in any order).
            self.assertEqual(sorted(cloud_ids(cloud)), list(range(m.particle_count)))
        finally:
            cloud_sub.close()
            stats.close()

    def test_04_container_markers_are_latched(self):
        # Raw bytes: visualization_msgs has no Python package in the Debian ROS we build on;
        # the type is checked in test_01.
        markers = Latest(NODE + '/markers', rospy.AnyMsg)
        m = markers.current_or_next(timeout=10.0)
        self.assertIn(b'container', m._buff)
        markers.close()

    def test_05_static_transform_world_to_fluid_domain(self):
        tf_static = Latest('/tf_static', TFMessage)
        m = tf_static.current_or_next(timeout=10.0, condition=lambda m: any(
            t.header.frame_id == 'world' and t.child_frame_id == 'fluid_domain'
            for t in m.transforms))
        self.assertIsNotNone(m)
        tf_static.close()

    def test_06_diagnostics_report_the_node(self):
        diagnostics = Latest('/diagnostics', DiagnosticArray)
        m = diagnostics.next(timeout=15.0, condition=lambda m: any(
            s.name == SIMULATION for s in m.status))
        status = [s for s in m.status if s.name == SIMULATION][0]
        keys = {kv.key for kv in status.values}
        self.assertIn('achieved real-time factor', keys)
        self.assertIn('average density error', keys)
        self.assertIn('NaN recoveries since reset', keys)
        diagnostics.close()

    def test_07_diagnostics_carry_the_cloud_rate_while_subscribed(self):
        name = SIMULATION.split(':')[0] + ': topic ' + NODE + '/particles'
        diagnostics = Latest('/diagnostics', DiagnosticArray)

        def cloud_status(condition):
            m = diagnostics.next(timeout=20.0, condition=lambda m: any(
                s.name == name and condition(s) for s in m.status))
            return [s for s in m.status if s.name == name][0]
        try:
            # Nobody listens (the earlier tests' subscribers are gone): idle, and OK.
            status = cloud_status(lambda s: s.message.startswith('idle'))
            self.assertEqual(status.level, DiagnosticStatus.OK)
            self.assertIn('no subscriber', status.message)
            clouds = cloud_listener()
            try:
                # Subscribed: FrequencyStatus measures the rate against ~publish_rate. Its
                # first report may span one short, uneven updater interval: read one whose
                # window holds at least a second's clouds.
                def measured_over_a_second(s):
                    values = {kv.key: kv.value for kv in s.values}
                    return 'Actual frequency (Hz)' in values and \
                        float(values.get('Events in window', 0)) >= PUBLISH_RATE
                status = cloud_status(measured_over_a_second)
                values = {kv.key: float(kv.value) for kv in status.values}
                self.assertAlmostEqual(values['Maximum acceptable frequency (Hz)'],
                                       PUBLISH_RATE * 1.1, places=3)
                self.assertAlmostEqual(values['Minimum acceptable frequency (Hz)'],
                                       PUBLISH_RATE * 0.5 * 0.9, places=3)
                self.assertGreater(values['Events in window'], 0)
                self.assertGreater(values['Actual frequency (Hz)'], 0.3 * PUBLISH_RATE)
                self.assertLess(values['Actual frequency (Hz)'], 1.2 * PUBLISH_RATE)
                self.assertGreater(clouds.count, 0)
            finally:
                clouds.close()
        finally:
            diagnostics.close()

    def test_08_diagnostics_come_at_the_updater_period(self):
        # Timed by the updater's own stamps, every message counted: how late each one is
        # delivered to this process does not enter the period.
        stamps = []
        cond = threading.Condition()

        def record(m):
            if any(s.name == SIMULATION for s in m.status):
                with cond:
                    stamps.append(m.header.stamp.to_sec())
                    cond.notify_all()
        sub = rospy.Subscriber('/diagnostics', DiagnosticArray, record, queue_size=20)
        try:
            with cond:
                self.assertTrue(cond.wait_for(lambda: len(stamps) >= 5, timeout=15.0),
                                'fewer than 5 diagnostics in 15 s: %s' % stamps)
                period = (stamps[4] - stamps[0]) / 4
            # node_interface.test sets ~diagnostic_period 0.5 (the default is 1 s).
            self.assertGreater(period, 0.35)
            self.assertLess(period, 0.75)
        finally:
            sub.unregister()


if __name__ == '__main__':
    rospy.init_node('test_node_interface')
    rostest.rosrun('pbf_ros', 'node_interface', NodeInterfaceTest)
