#!/usr/bin/python3
"""Drives the pouring arm (urdf/pouring_arm.urdf) through a pour: publishes
sensor_msgs/JointState on joint_states for robot_state_publisher.

The trajectory is a list of keyframes [time, x, z, pitch]: where the cup's frame (on the
wrist axis, 3 cm below the cup's bottom) is relative to the shoulder axis, in the arm's vertical
plane [m], and the cup's pitch [rad] (0 upright, > 0 tipping its opening towards +x), at
that simulated time [s]. Between keyframes the cup moves smoothly (cosine ramp) in x, z and
pitch; the three pitch joints follow from the planar inverse kinematics (elbow up). After
the last keyframe the arm holds still.

  ~keyframes  list of [t, x, z, pitch] (default: fill under the tap, hold, carry, pour, hold)
  ~rate       [Hz] of simulated time (default 100)
  ~lookahead  [s] (default 0.05)
  ~stats      the fluid node's statistics topic (default /fluid/stats)

The keyframe times are the fluid's simulated time, which a ~reset of the node sets back to 0
(the tap opens again at its `start`) while /clock goes on: the node's ~stats carry both (the
header's stamp on /clock, sim_time the fluid's), so the arm starts its pour over with the
fluid instead of holding its cup tipped while the tap runs again.

Follows /clock (the demo's node publishes it). Each joint state is stamped ~lookahead ahead
of the clock (the trajectory is known in advance, like a controller's set point): the node
looks the links up at each step's time and finds tf already there to interpolate, instead
of waiting up to 20 ms per step for the round trip through robot_state_publisher. Before /clock runs, the node waits for the
arm's tf to place its links: the start pose is published then, latched, stamped at
~startup_stamp (default 0.02 s, robot_state_publisher's publish interval: it skips stamps
closer than that to the last one it published, which starts at 0), and offered again every
0.1 s of wall time until /clock runs (see STARTUP_REPEAT).
"""
import math
import threading
import time

import rospy
from pbf_ros.msg import SimulationStats
from sensor_msgs.msg import JointState

UPPER_ARM, FOREARM = 0.22, 0.18  # shoulder -> elbow -> wrist [m], from the URDF
JOINTS = ('shoulder', 'elbow', 'wrist')
LIMITS = (1.8, 2.4, 2.6)         # the URDF's |joint| limits [rad]
# [wall s] Before /clock runs, the start pose goes out again this often. Latching reaches a
# late robot_state_publisher, but its tf (on /tf, not latched) went out once: a tf listener
# that subscribed after it, such as the fluid node's when it starts a few tenths of a second
# later than this script, never saw the arm and left its links out after ~robot_tf_wait.
STARTUP_REPEAT = 0.1

# Fill under the tap (0.3 - 0.6 s), let the water settle and hold still (to 2.2 s), carry the
# upright cup over the basin (to 3.0 s), tip it (to 4.0 s) and hold it tipped.
DEFAULT_KEYFRAMES = [
    [0.0, 0.22, 0.14, 0.0],
    [2.2, 0.22, 0.14, 0.0],
    [3.0, 0.33, 0.14, 0.0],
    [4.0, 0.33, 0.14, 2.1],
]


def inverse_kinematics(x, z, pitch):
    """Joint angles (shoulder, elbow, wrist) putting the wrist at (x, z) from the shoulder
    with the cup at `pitch`; angles about +y, so +z turns towards +x. Elbow up."""
    d2 = x * x + z * z
    c = (d2 - UPPER_ARM ** 2 - FOREARM ** 2) / (2.0 * UPPER_ARM * FOREARM)
    if abs(c) > 1.0:
        raise ValueError('the wrist cannot reach (%.3f, %.3f)' % (x, z))
    elbow = math.acos(c)
    shoulder = math.atan2(x, z) - math.atan2(FOREARM * math.sin(elbow),
                                             UPPER_ARM + FOREARM * math.cos(elbow))
    return shoulder, elbow, pitch - shoulder - elbow


def cup_at(keyframes, t):
    """(x, z, pitch) at time t: cosine-ramped between keyframes, held outside them."""
    if t <= keyframes[0][0]:
        return keyframes[0][1:]
    for a, b in zip(keyframes, keyframes[1:]):
        if t <= b[0]:
            s = 0.5 - 0.5 * math.cos(math.pi * (t - a[0]) / (b[0] - a[0]))
            return [a[i] + s * (b[i] - a[i]) for i in (1, 2, 3)]
    return keyframes[-1][1:]


def check(keyframes):
    """Raises ValueError naming the first keyframe that is unusable."""
    if not isinstance(keyframes, list) or not keyframes:
        raise ValueError('~keyframes: expected a list of [t, x, z, pitch], got %r' % (keyframes,))
    for k, frame in enumerate(keyframes):
        # bool is an int in Python: a `true` among the numbers is not one.
        if (not isinstance(frame, list) or len(frame) != 4 or
                not all(isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
                        for v in frame)):
            raise ValueError('~keyframes[%d]: expected [t, x, z, pitch] (finite numbers), got %r' % (k, frame))
        if k > 0 and frame[0] <= keyframes[k - 1][0]:
            raise ValueError('~keyframes[%d]: times must increase' % k)
        angles = inverse_kinematics(*frame[1:])
        for name, angle, limit in zip(JOINTS, angles, LIMITS):
            if abs(angle) > limit:
                raise ValueError('~keyframes[%d]: joint %s at %.2f rad is beyond its limit %.1f'
                                 % (k, name, angle, limit))


class FluidTime:
    """The fluid's simulated time at a /clock time: /clock minus where the fluid's time last
    restarted (0 until the node says otherwise), from the node's ~stats."""

    def __init__(self):
        self._lock = threading.Lock()
        self._offset = 0.0

    def on_stats(self, msg):
        with self._lock:
            self._offset = msg.header.stamp.to_sec() - msg.sim_time

    def at(self, clock):
        with self._lock:
            return clock - self._offset


def message(stamp, angles):
    msg = JointState()
    msg.header.stamp = stamp
    msg.name = list(JOINTS)
    msg.position = list(angles)
    return msg


def main():
    rospy.init_node('pouring_arm_trajectory')
    keyframes = rospy.get_param('~keyframes', DEFAULT_KEYFRAMES)

    def number(name, default):
        value = rospy.get_param(name, default)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise ValueError('%s: expected a finite number, got %r' % (name, value))
        return float(value)

    try:
        rate_hz = number('~rate', 100.0)
        startup_stamp = number('~startup_stamp', 0.02)
        lookahead = number('~lookahead', 0.05)
        check(keyframes)
        if not 0.0 < rate_hz <= 10000.0:
            raise ValueError('~rate must be in (0, 10000] Hz')
        if not 0.0 < startup_stamp <= 60.0:
            raise ValueError('~startup_stamp must be in (0, 60] s')
        if not 0.0 <= lookahead <= 1.0:
            raise ValueError('~lookahead must be in [0, 1] s')
    except ValueError as e:
        rospy.logfatal('pouring_arm_trajectory: %s', e)
        raise SystemExit(2)
    fluid_time = FluidTime()
    rospy.Subscriber(rospy.get_param('~stats', '/fluid/stats'), SimulationStats,
                     fluid_time.on_stats, queue_size=1)
    pub = rospy.Publisher('joint_states', JointState, queue_size=10, latch=True)
    start = inverse_kinematics(*cup_at(keyframes, 0.0))
    # Wall-clock waits: simulated time does not move before /clock does. Each repeat of the
    # start pose is 1 ns later than the one before: robot_state_publisher publishes it (before
    # /clock it compares stamps with 0), and tf2 listeners that have the earlier one keep it
    # instead of refusing the same stamp again (TF_REPEATED_DATA). A day of waiting adds < 1 ms.
    repeats = 0
    next_offer = time.monotonic()
    while not rospy.is_shutdown() and rospy.Time.now().is_zero():
        if time.monotonic() >= next_offer:
            stamp = rospy.Time.from_sec(startup_stamp) + rospy.Duration(0, repeats)
            pub.publish(message(stamp, start))
            repeats += 1
            next_offer = time.monotonic() + STARTUP_REPEAT
        time.sleep(0.02)
    last = None
    while not rospy.is_shutdown():
        now = rospy.Time.now()
        if now == last:  # the simulation is slower than real time: wait for a new stamp
            time.sleep(0.002)
            continue
        last = now
        ahead = now + rospy.Duration.from_sec(lookahead)
        t = fluid_time.at(ahead.to_sec())
        pub.publish(message(ahead, inverse_kinematics(*cup_at(keyframes, t))))
        try:
            rospy.sleep(1.0 / rate_hz)
        except rospy.ROSInterruptException:
            break


if __name__ == '__main__':
    main()
