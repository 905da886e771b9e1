#!/usr/bin/python3
"""~reset after the frame a container is attached to has moved and turned: the fluid starts
inside the container where it is now, not where it stood at rest (issue 11, item 5)."""
import math
import unittest

import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import TransformStamped
from std_srvs.srv import SetBool, Trigger

from fluid_test_util import NODE, cloud_listener, cloud_points, mean

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


if __name__ == '__main__':
    rospy.init_node('test_reset_moved_frame')
    rostest.rosrun('pbf_ros', 'reset_moved_frame', ResetMovedFrameTest)
