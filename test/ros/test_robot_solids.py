#!/usr/bin/python3
"""A robot's links as solids (issue 12, part 1 and 2), on probe_robot.urdf: its box link in
the tank keeps the fluid out and feels the water's buoyancy; a link whose mesh is missing
a degenerate mesh and a link without tf are reported by name while the rest takes part; a
new URDF on the parameter server is read on ~reset and on a scene switch, and one that does
not parse is reported while the fluid runs on; a link ~robot_link_regex leaves out is no
solid; wrenches are measured only while asked for, and come at ~wrench_rate."""
import os
import threading
import time
import unittest

import dynamic_reconfigure.client
import rospkg
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped, WrenchStamped
from rosgraph_msgs.msg import Log
from std_srvs.srv import Trigger
from visualization_msgs.msg import Marker, MarkerArray

from fluid_test_util import (NODE, Latest, cloud_listener, cloud_points, stats_listener,
                             wait_connected)

# The probe link in fluid_domain (base_link at its origin): 1.75 spacings of water under and
# over it. (At 0.12 only one particle layer was left under it, which cannot carry the
# hydrostatic pressure at this resolution: 0.70 of the buoyancy with the Spiky density.)
CENTRE = (0.2, 0.2, 0.15)
HALF = 0.08                # the probe's half size [m]
SPACING = 0.04
RHO_G = 1000.0 * 9.81


def place_robot_base():
    broadcaster = tf2_ros.StaticTransformBroadcaster()
    t = TransformStamped()
    t.header.stamp = rospy.Time.now()
    t.header.frame_id = 'fluid_domain'
    t.child_frame_id = 'base_link'
    t.transform.rotation.w = 1.0
    broadcaster.sendTransform(t)
    return broadcaster


class RosoutRecorder:
    def __init__(self):
        self.lock = threading.Lock()
        self.lines = []
        self.sub = rospy.Subscriber('/rosout', Log, self.callback, queue_size=100)
        wait_connected(self.sub)  # the node's lines on the ~reset that follows

    def callback(self, msg):
        with self.lock:
            self.lines.append((msg.level, msg.msg))

    def wait_for(self, level, *words, timeout=15.0):
        deadline = time.time() + timeout
        while time.time() < deadline:
            with self.lock:
                for lvl, text in self.lines:
                    if lvl == level and all(w in text for w in words):
                        return text
            time.sleep(0.05)
        with self.lock:
            seen = '\n'.join(t for _, t in self.lines)
        raise AssertionError('no log line with %s at level %d; saw:\n%s' % (words, level, seen))


def probe_markers(markers):
    return [m for m in markers.markers if m.header.frame_id == 'probe']


class RobotSolidsTest(unittest.TestCase):

    def test_robot_links_take_part(self):
        self.broadcaster = place_robot_base()
        stats = stats_listener()
        try:
            s = stats.next(timeout=60.0, condition=lambda m: m.sim_time > 1.0)
            # Nobody asks for a wrench yet: none is measured (lazily).
            self.assertIn('wrench', s.skipped_stages)
            self.assertFalse(s.wrench_tracked)
        finally:
            stats.close()

        # The probe's box keeps every particle out; the fluid is still all there around it.
        clouds = cloud_listener()
        try:
            points = cloud_points(clouds.next(timeout=10.0))
        finally:
            clouds.close()
        inner = HALF - 0.25 * SPACING
        inside = [p for p in points if all(abs(p[a] - CENTRE[a]) < inner for a in range(3))]
        self.assertEqual(inside, [], 'particles inside the probe link')
        self.assertGreater(len(points), 500)

        # Its marker is drawn in the link's frame, the size of its collision box.
        markers = Latest(NODE + '/markers', MarkerArray).current_or_next(timeout=10.0)
        cubes = [m for m in probe_markers(markers) if m.type == Marker.CUBE]
        self.assertEqual(len(cubes), 1)
        self.assertAlmostEqual(cubes[0].scale.x, 2 * HALF, places=4)
        # The link ~robot_link_regex leaves out is no solid: no marker, no wrench topic.
        self.assertEqual([m for m in markers.markers if m.header.frame_id == 'skipped'], [])
        topics = [t for t, _ in rospy.get_published_topics(NODE)]
        self.assertIn(NODE + '/wrench/probe', topics)
        self.assertNotIn(NODE + '/wrench/skipped', topics)

        # The water pushes it up: Archimedes (coarse: 4 particles across it, hence 30 %).
        wrenches = Latest(NODE + '/wrench/probe', WrenchStamped)
        container = Latest(NODE + '/wrench/container', WrenchStamped)
        stats = stats_listener()
        try:
            lift = []
            wrenches.next(timeout=10.0)  # measuring has started
            # The rate from every message the subscriber received (its count), not from
            # this loop's wake-ups: on a loaded host two messages can arrive between them.
            start, received = time.time(), wrenches.count
            while time.time() < start + 4.0:
                w = wrenches.next(timeout=10.0)
                self.assertEqual(w.header.frame_id, 'probe')
                lift.append(w.wrench.force.z)
            rate = (wrenches.count - received) / (time.time() - start)
            rospy.loginfo('~wrench/probe at %.1f Hz (~wrench_rate 10)', rate)
            self.assertGreater(rate, 5.0)
            self.assertLess(rate, 12.0)
            buoyancy = RHO_G * (2 * HALF) ** 3
            mean_lift = sum(lift) / len(lift)
            rospy.loginfo('probe lift %.2f N vs rho0 g V %.2f N', mean_lift, buoyancy)
            self.assertGreater(mean_lift, 0.7 * buoyancy)
            self.assertLess(mean_lift, 1.3 * buoyancy)
            self.assertLess(container.next(timeout=10.0).wrench.force.z, 0.0)
            s = stats.next(timeout=10.0, condition=lambda m: m.wrench_tracked)
            self.assertNotIn('wrench', s.skipped_stages)
            self.assertLess(s.solids_wrench.force.z, 0.0)  # the fluid's weight, on its solids
        finally:
            wrenches.close()
            container.close()
            stats.close()

        # Bad links are reported by name on every (re)load, and a new URDF is read on ~reset:
        # the probe becomes a sphere.
        log = RosoutRecorder()
        marker_topic = Latest(NODE + '/markers', MarkerArray)
        marker_topic.connected()
        urdf = rospy.get_param('/robot_description')
        rospy.set_param('/robot_description', urdf.replace(
            '<box size="0.16 0.16 0.16"/>', '<sphere radius="0.08"/>'))
        reset = rospy.ServiceProxy(NODE + '/reset', Trigger)
        reset.wait_for_service(timeout=10.0)
        answer = reset()
        self.assertTrue(answer.success, answer.message)
        log.wait_for(Log.WARN, "'lost'", 'no_such_mesh.stl')
        log.wait_for(Log.WARN, "'flat'", 'no volume')
        log.wait_for(Log.ERROR, "'swing'", 'no tf')
        markers = marker_topic.current_or_next(
            timeout=10.0, condition=lambda m: any(p.type == Marker.SPHERE for p in probe_markers(m)))
        self.assertEqual([m.type for m in probe_markers(markers)], [Marker.SPHERE])
        stats = stats_listener()
        try:
            s = stats.next(timeout=20.0, condition=lambda m: m.sim_time > 0.3)
            self.assertGreater(s.particle_count, 500)
        finally:
            stats.close()

        # A URDF that does not parse: said so, and the fluid runs on without the robot.
        rospy.set_param('/robot_description', '<robot name="broken"><link name="a">')
        answer = reset()
        self.assertTrue(answer.success, answer.message)
        log.wait_for(Log.WARN, 'not a valid URDF')
        marker_topic.current_or_next(timeout=10.0, condition=lambda m: not probe_markers(m))
        stats = stats_listener()
        try:
            s = stats.next(timeout=20.0, condition=lambda m: m.sim_time > 0.3)
            self.assertGreater(s.particle_count, 500)
        finally:
            stats.close()

        # A scene switch (dynamic_reconfigure) reads the URDF again too: the probe is back.
        rospy.set_param('/robot_description', urdf)
        scene = os.path.join(rospkg.RosPack().get_path('pbf_ros'), 'test', 'scenes', 'coarse_tank.yaml')
        dynamic_reconfigure.client.Client(NODE, timeout=10.0).update_configuration({'scene': scene})
        markers = marker_topic.current_or_next(
            timeout=20.0, condition=lambda m: any(p.type == Marker.CUBE for p in probe_markers(m)))
        self.assertEqual([m.type for m in probe_markers(markers)], [Marker.CUBE])

        # The description deleted, then ~reset: the robot goes, and the node says so (it went
        # in silence, as for a scene that never had one).
        rospy.delete_param('/robot_description')
        try:
            answer = reset()
            self.assertTrue(answer.success, answer.message)
            log.wait_for(Log.WARN, 'robot description', 'is gone')
            marker_topic.current_or_next(timeout=10.0, condition=lambda m: not probe_markers(m))
        finally:
            rospy.set_param('/robot_description', urdf)


if __name__ == '__main__':
    rospy.init_node('test_robot_solids')
    rostest.rosrun('pbf_ros', 'robot_solids', RobotSolidsTest)
