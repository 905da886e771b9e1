#!/usr/bin/python3
"""Moves a tf frame for the boundary demos: broadcasts parent -> child at a fixed rate.

  ~mode:      'slosh' (translate back and forth along ~axis) or 'tilt' (rotate about ~axis
              through ~pivot, ramping from 0 to ~angle after ~delay over ~duration, then hold)
  ~parent, ~child: frame names (defaults fluid_domain -> tank)
  ~amplitude [m], ~period [s]                   (slosh)
  ~pivot [x, y, z], ~angle [rad], ~delay [s], ~duration [s]   (tilt)
  ~axis: [x, y, z], ~rate [Hz]

At rest (t = 0, or angle 0) the child coincides with the parent, which is how the sloshing
and pouring scenes define their geometry. Follows /clock when use_sim_time is set.
"""
import math

import rospy
import tf2_ros
from geometry_msgs.msg import TransformStamped


def quaternion_about(axis, angle):
    norm = math.sqrt(sum(a * a for a in axis))
    x, y, z = (a / norm for a in axis)
    s = math.sin(angle / 2.0)
    return x * s, y * s, z * s, math.cos(angle / 2.0)


def rotate(q, v):
    """Rotates vector v by unit quaternion q = (x, y, z, w)."""
    x, y, z, w = q
    # v' = v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)
    ux = (y * v[2] - z * v[1], z * v[0] - x * v[2], x * v[1] - y * v[0])
    uux = (y * ux[2] - z * ux[1], z * ux[0] - x * ux[2], x * ux[1] - y * ux[0])
    return tuple(v[i] + 2.0 * w * ux[i] + 2.0 * uux[i] for i in range(3))


def main():
    rospy.init_node("move_frame")
    mode = rospy.get_param("~mode", "slosh")
    if mode not in ("slosh", "tilt"):
        rospy.logfatal("~mode must be 'slosh' or 'tilt', got '%s'", mode)
        raise SystemExit(2)
    parent = rospy.get_param("~parent", "fluid_domain")
    child = rospy.get_param("~child", "tank")
    def number(name, default):
        """A finite number, or exit naming the parameter (NaN went out on /tf)."""
        value = rospy.get_param("~" + name, default)
        try:
            value = float(value)
        except (TypeError, ValueError):
            value = float("nan")
        if not math.isfinite(value):
            rospy.logfatal("move_frame: ~%s must be a finite number, got %r", name, rospy.get_param("~" + name))
            raise SystemExit(2)
        return value

    def vector(name, default):
        """Three finite numbers, or exit naming the parameter."""
        value = rospy.get_param("~" + name, default)
        try:
            value = [float(v) for v in value]
        except (TypeError, ValueError):
            value = []
        if len(value) != 3 or not all(math.isfinite(v) for v in value):
            rospy.logfatal("move_frame: ~%s must be three finite numbers, got %r", name, rospy.get_param("~" + name))
            raise SystemExit(2)
        return value

    axis = vector("axis", [1.0, 0.0, 0.0] if mode == "slosh" else [0.0, 1.0, 0.0])
    rate_hz = number("rate", 60.0)
    amplitude = number("amplitude", 0.05)
    period = number("period", 1.2)
    pivot = vector("pivot", [0.0, 0.0, 0.0])
    angle = number("angle", 2.0)
    delay = number("delay", 1.0)
    duration = number("duration", 3.0)
    # At most 1 kHz: a tf publisher faster than that only floods the graph.
    if period <= 0.0 or duration <= 0.0 or not 0.0 < rate_hz <= 1000.0 or delay < 0.0:
        rospy.logfatal("move_frame: need ~period, ~duration > 0, ~delay >= 0 and 0 < ~rate <= 1000 Hz")
        raise SystemExit(2)
    if math.sqrt(sum(a * a for a in axis)) < 1e-9:
        rospy.logfatal("move_frame: ~axis must not be zero")
        raise SystemExit(2)

    broadcaster = tf2_ros.TransformBroadcaster()
    rate = rospy.Rate(rate_hz)
    start = None
    last_stamp = None
    while not rospy.is_shutdown():
        now = rospy.Time.now()
        # Sim time not started yet, or not advanced since the last publish (the simulation
        # runs slower than real time): tf2 rejects a repeated stamp, so wait for a new one.
        if now.is_zero() or now == last_stamp:
            rospy.sleep(0.005)
            continue
        last_stamp = now
        if start is None:
            start = now
        t = (now - start).to_sec()
        msg = TransformStamped()
        msg.header.stamp = now
        msg.header.frame_id = parent
        msg.child_frame_id = child
        if mode == "slosh":
            offset = amplitude * math.sin(2.0 * math.pi * t / period)
            norm = math.sqrt(sum(a * a for a in axis))
            msg.transform.translation.x, msg.transform.translation.y, msg.transform.translation.z = (
                offset * a / norm for a in axis)
            msg.transform.rotation.w = 1.0
        else:
            ramp = min(max((t - delay) / duration, 0.0), 1.0)
            # Smooth start and stop (no jerk at either end of the pour).
            theta = angle * (0.5 - 0.5 * math.cos(math.pi * ramp))
            q = quaternion_about(axis, theta)
            rotated_pivot = rotate(q, pivot)
            # Rotation about the pivot: x -> R (x - p) + p.
            msg.transform.translation.x = pivot[0] - rotated_pivot[0]
            msg.transform.translation.y = pivot[1] - rotated_pivot[1]
            msg.transform.translation.z = pivot[2] - rotated_pivot[2]
            (msg.transform.rotation.x, msg.transform.rotation.y,
             msg.transform.rotation.z, msg.transform.rotation.w) = q
        broadcaster.sendTransform(msg)
        try:
            rate.sleep()
        except rospy.ROSInterruptException:
            break


if __name__ == "__main__":
    main()
