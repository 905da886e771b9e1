#!/usr/bin/python3
"""~reset after the frame a container is attached to has moved and turned: the fluid starts
inside the container where it is now, not where it stood at rest (issue 11, item 5). A block
of fluid whose frame has left the container is left out with a warning, and a reset that
would leave no particle in the container is refused: clamped into it, such particles started
piled on its walls and burst out at 18 m/s."""
import math
import os
import unittest

import dynamic_reconfigure.client
import rospkg
import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped
from std_srvs.srv import SetBool, Trigger

from fluid_test_util import NODE, cloud_listener, cloud_points, mean, stats_listener

OFFSET = (0.6, 0.3, 0.0)  # the tank frame in fluid_domain [m]
YAW = 0.5                 # [rad]
SIZE = (0.5, 0.5, 0.5)    # moved_tank.yaml's container, in the tank frame
SPACING = 0.05


def in_tank_frame(p):
    """A fluid_domain point in the tank frame."""
    x, y, z = p[0] - OFFSET[0], p[1] - OFFSET[1], p[2] - OFFSET[2]
    c, s = math.cos(YAW), math.sin(YAW)
    return (c * x + s * y, -s * x + c * y, z)


class ResetMovedFrameTest(unittest.TestCase):

    def test_reset_seeds_the_fluid_where_the_container_is_now(self):
        broadcaster = tf2_ros.StaticTransformBroadcaster()
        t = TransformStamped()
        t.header.stamp = rospy.Time.now()
        t.header.frame_id = 'fluid_domain'
        t.child_frame_id = 'tank'
        t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = OFFSET
        t.transform.rotation.z = math.sin(YAW / 2)
        t.transform.rotation.w = math.cos(YAW / 2)
        broadcaster.sendTransform(t)

        rospy.wait_for_service(NODE + '/reset', timeout=30.0)
        pause = rospy.ServiceProxy(NODE + '/pause', SetBool)
        reset = rospy.ServiceProxy(NODE + '/reset', Trigger)
        # Until the node has the frame: the moved walls push the fluid towards +x.
        clouds = cloud_listener()
        try:
            clouds.next(timeout=30.0,
                        condition=lambda m: max(p[0] for p in cloud_points(m)) > 0.55)
        finally:
            clouds.close()
        self.assertTrue(pause(True).success)
        response = reset()
        self.assertTrue(response.success, response.message)
        clouds = cloud_listener()  # a newcomer gets the (paused) state
        try:
            points = [p[:3] for p in cloud_points(clouds.current_or_next(timeout=20.0))]
        finally:
            clouds.close()
        self.assertGreater(len(points), 100)
        tol = 0.5 * SPACING
        for p in points:
            q = in_tank_frame(p)
            for axis in range(3):
                self.assertTrue(-tol <= q[axis] <= SIZE[axis] + tol,
                                'particle %s is outside the moved tank (tank frame %s)' % (p, q))
        # At rest the fluid's centre would be at (0.25, 0.25); now it moved with the tank.
        centre = in_tank_frame((mean(p[0] for p in points), mean(p[1] for p in points), 0.0))
        self.assertAlmostEqual(centre[0], 0.25, delta=0.03)
        self.assertAlmostEqual(centre[1], 0.25, delta=0.03)

    def test_seeded_fluid_outside_the_container_is_left_out_or_the_reset_refused(self):
        # Runs after the test above (names in order): its scene is switched here.
        broadcaster = tf2_ros.StaticTransformBroadcaster()
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)

        def move_cup(x):
            t = TransformStamped()
            t.header.stamp = rospy.Time.now()
            t.header.frame_id = 'fluid_domain'
            t.child_frame_id = 'cup'
            t.transform.translation.x = x
            t.transform.rotation.w = 1.0
            broadcaster.sendTransform(t)
            deadline = rospy.Time.now() + rospy.Duration(10.0)
            while rospy.Time.now() < deadline:  # until tf carries it (the node's listener too)
                try:
                    if abs(buffer.lookup_transform('fluid_domain', 'cup', rospy.Time(0))
                           .transform.translation.x - x) < 1e-9:
                        rospy.sleep(0.5)
                        return
                except tf2_ros.TransformException:
                    pass
                rospy.sleep(0.05)
            self.fail('tf never carried cup at x = %g' % x)

        reset = rospy.ServiceProxy(NODE + '/reset', Trigger)
        stats = stats_listener()
        try:
            move_cup(0.0)
            scene = os.path.join(rospkg.RosPack().get_path('pbf_ros'), 'test', 'scenes', 'cup_block.yaml')
            config = dynamic_reconfigure.client.Client(NODE, timeout=30.0).update_configuration({'scene': scene})
            self.assertEqual(config['scene'], scene)
            self.assertTrue(reset().success)
            full = stats.next(timeout=20.0).particle_count
            self.assertEqual(full, 64)  # 4 x 4 x 4 at 0.05 m

            # Wholly outside (x + 5 m): refused by name, the running fluid kept.
            move_cup(5.0)
            response = reset()
            self.assertFalse(response.success)
            self.assertIn('outside the container', response.message)
            self.assertIn("frame 'cup'", response.message)
            self.assertEqual(stats.next(timeout=20.0).particle_count, full)

            # Half outside (its block then spans x 0.4 ... 0.6 in a tank 0.5 long): those left out.
            move_cup(0.3)
            response = reset()
            self.assertTrue(response.success, response.message)
            clouds = cloud_listener()
            try:
                points = [p[:3] for p in cloud_points(clouds.current_or_next(timeout=20.0))]
            finally:
                clouds.close()
            self.assertTrue(0 < len(points) < full, len(points))
            self.assertLessEqual(max(p[0] for p in points), 0.5)
        finally:
            stats.close()


if __name__ == '__main__':
    rospy.init_node('test_reset_moved_frame')
    rostest.rosrun('pbf_ros', 'reset_moved_frame', ResetMovedFrameTest)
