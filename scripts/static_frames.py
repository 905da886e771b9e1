#!/usr/bin/python3
"""Publishes fixed tf frames on /tf_static (Debian's ROS has no tf2_ros
static_transform_publisher executable): one latched message with every frame of ~frames.

  ~frames: list of {parent: P, child: C, xyz: [x, y, z], rpy: [roll, pitch, yaw]}
           (xyz [m] and rpy [rad] default to zero)

A bad entry is refused by name (exit code 2); nothing is published then.
"""
import math

import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped


def quaternion_from_rpy(roll, pitch, yaw):
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return (sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy, cr * cp * cy + sr * sp * sy)


def transform(entry, index):
    """The TransformStamped of one ~frames entry; ValueError naming what is wrong."""
    where = '~frames[%d]' % index
    if not isinstance(entry, dict):
        raise ValueError('%s: expected a map with parent, child, xyz, rpy' % where)
    unknown = set(entry) - {'parent', 'child', 'xyz', 'rpy'}
    if unknown:
        raise ValueError('%s: unknown key(s) %s' % (where, ', '.join(sorted(unknown))))
    for key in ('parent', 'child'):
        if not isinstance(entry.get(key), str) or not entry[key]:
            raise ValueError('%s.%s: expected a frame name' % (where, key))
    values = {}
    for key in ('xyz', 'rpy'):
        v = entry.get(key, [0.0, 0.0, 0.0])
        if not (isinstance(v, list) and len(v) == 3 and
                all(isinstance(x, (int, float)) and math.isfinite(x) for x in v)):
            raise ValueError('%s.%s: expected 3 finite numbers, got %r' % (where, key, v))
        values[key] = [float(x) for x in v]
    t = TransformStamped()
    t.header.stamp = rospy.Time(0)
    t.header.frame_id = entry['parent']
    t.child_frame_id = entry['child']
    t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = values['xyz']
    (t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
     t.transform.rotation.w) = quaternion_from_rpy(*values['rpy'])
    return t


def main():
    rospy.init_node('static_frames')
    frames = rospy.get_param('~frames', [])
    try:
        if not isinstance(frames, list) or not frames:
            raise ValueError('~frames: expected a non-empty list')
        transforms = [transform(entry, k) for k, entry in enumerate(frames)]
    except ValueError as e:
        rospy.logfatal('static_frames: %s', e)
        raise SystemExit(2)
    broadcaster = tf2_ros.StaticTransformBroadcaster()
    broadcaster.sendTransform(transforms)
    rospy.spin()


if __name__ == '__main__':
    main()
