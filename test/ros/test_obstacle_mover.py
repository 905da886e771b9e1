#!/usr/bin/python3
"""Moving a scene's free obstacles while the fluid runs: only the free sphere (obstacle_0)
gets an interactive marker and a ~obstacle_pose topic (not the tf-attached box, not the
floating ball); a PoseStamped moves it across the pool in bounded steps (no particle ends up
inside it), a non-finite pose is refused while the fluid runs on, and a drag from rviz (the
marker server's feedback) moves it back."""
import math
import time
import unittest

import rosgraph
import rospy
import rostest
from geometry_msgs.msg import PoseStamped
from visualization_msgs.msg import InteractiveMarkerFeedback, InteractiveMarkerInit, MarkerArray

from fluid_test_util import NODE, Latest, cloud_listener, cloud_points, stats_listener

RADIUS, SPACING = 0.04, 0.025


def sphere_marker(markers):
    """The free sphere's marker (ns obstacles, id 0) in ~markers, or None."""
    for m in markers.markers:
        if m.ns == 'obstacles' and m.id == 0 and m.action == m.ADD:
            return m
    return None


def pose_stamped(x, y, z, frame='fluid_domain', w=1.0):
    msg = PoseStamped()
    msg.header.frame_id = frame
    msg.pose.position.x, msg.pose.position.y, msg.pose.position.z = x, y, z
    msg.pose.orientation.w = w
    return msg


class ObstacleMoverTest(unittest.TestCase):

    @classmethod
    def setUpClass(cls):
        cls.markers = Latest(NODE + '/markers', MarkerArray)
        cls.stats = stats_listener()
        cls.stats.next(timeout=30.0)

    def wait_for_sphere_at(self, x, y, z, timeout=30.0):
        def there(msg):
            m = sphere_marker(msg)
            return m is not None and math.dist((m.pose.position.x, m.pose.position.y, m.pose.position.z),
                                               (x, y, z)) < 1e-4
        return self.markers.current_or_next(timeout=timeout, condition=there)

    def test_1_only_the_free_obstacle_can_be_moved(self):
        init = Latest(NODE + '/obstacle_markers/update_full', InteractiveMarkerInit).current_or_next(
            timeout=30.0)
        self.assertEqual([m.name for m in init.markers], ['obstacle_0'])
        self.assertEqual(init.markers[0].header.frame_id, 'fluid_domain')
        _, subscribers, _ = rosgraph.Master('/test').getSystemState()[:3]
        topics = [t for t, _ in subscribers]
        self.assertIn(NODE + '/obstacle_pose/obstacle_0', topics)
        self.assertNotIn(NODE + '/obstacle_pose/obstacle_1', topics)
        self.assertNotIn(NODE + '/obstacle_pose/obstacle_2', topics)

    def test_2_a_pose_moves_it_and_a_bad_pose_changes_nothing(self):
        pub = rospy.Publisher(NODE + '/obstacle_pose/obstacle_0', PoseStamped, queue_size=1)
        deadline = time.time() + 10.0
        while pub.get_num_connections() == 0 and time.time() < deadline:
            time.sleep(0.05)
        self.assertGreater(pub.get_num_connections(), 0,
                           'the node never subscribed to ' + pub.resolved_name)
        start = self.stats.next(timeout=10.0)
        pub.publish(pose_stamped(0.3, 0.15, 0.06))
        self.wait_for_sphere_at(0.3, 0.15, 0.06)
        arrived = self.stats.next(timeout=10.0)
        # 20 cm at half a spacing per step: at least 16 steps, never a jump.
        self.assertGreaterEqual(arrived.step_count - start.step_count, 16)
        # The fluid was swept aside: no particle centre inside the sphere (the solver keeps
        # them a particle radius out).
        clouds = cloud_listener()
        try:
            cloud = clouds.next(timeout=10.0)
        finally:
            clouds.close()
        nearest = min(math.dist(p[:3], (0.3, 0.15, 0.06)) for p in cloud_points(cloud))
        self.assertGreater(nearest, RADIUS + 0.4 * SPACING)

        # Non-finite and degenerate poses are refused; the sphere stays, the fluid runs on.
        pub.publish(pose_stamped(float('nan'), 0.15, 0.06))
        pub.publish(pose_stamped(0.2, 0.15, 0.06, w=0.0))
        pub.publish(pose_stamped(0.2, 0.15, 0.06, frame='no_such_frame'))
        before = self.stats.next(timeout=10.0)
        later = self.stats.next(timeout=10.0, condition=lambda m: m.sim_time > before.sim_time + 0.5)
        self.assertTrue(math.isfinite(later.max_speed))
        self.assertLess(later.max_speed, 3.0)
        m = sphere_marker(self.markers.current_or_next(timeout=5.0))
        self.assertAlmostEqual(m.pose.position.x, 0.3, delta=1e-4)

    def test_3_a_drag_in_rviz_moves_it_back(self):
        feedback = rospy.Publisher(NODE + '/obstacle_markers/feedback', InteractiveMarkerFeedback,
                                   queue_size=1)
        deadline = time.time() + 10.0
        while feedback.get_num_connections() == 0 and time.time() < deadline:
            time.sleep(0.05)
        self.assertGreater(feedback.get_num_connections(), 0,
                           'the node never subscribed to ' + feedback.resolved_name)
        f = InteractiveMarkerFeedback()
        f.client_id = '/rviz/InteractiveMarkers'
        f.marker_name = 'obstacle_0'
        f.event_type = InteractiveMarkerFeedback.POSE_UPDATE
        f.header.frame_id = 'fluid_domain'
        f.pose = pose_stamped(0.12, 0.15, 0.06).pose
        feedback.publish(f)
        self.wait_for_sphere_at(0.12, 0.15, 0.06)


if __name__ == '__main__':
    rospy.init_node('test_obstacle_mover')
    rostest.rosrun('pbf_ros', 'obstacle_mover', ObstacleMoverTest)
