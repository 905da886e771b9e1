"""Helpers shared by the pbf_node rostest nodes."""
import struct
import threading
import time

import rospy
from pbf_ros.msg import SimulationStats
from sensor_msgs.msg import PointCloud2

NODE = '/fluid'


class Latest:
    """Subscribes to a topic and keeps the latest message (and a count)."""

    def __init__(self, topic, msg_type):
        self._cond = threading.Condition()
        self.msg = None
        self.count = 0
        self.sub = rospy.Subscriber(topic, msg_type, self._callback, queue_size=5)

    def _callback(self, msg):
        with self._cond:
            self.msg = msg
            self.count += 1
            self._cond.notify_all()

    def next(self, timeout=10.0, condition=lambda m: True):
        """Waits for a message that arrives after this call and satisfies condition."""
        deadline = time.time() + timeout
        with self._cond:
            start = self.count
            while True:
                if self.count > start and condition(self.msg):
                    return self.msg
                remaining = deadline - time.time()
                if remaining <= 0:
                    raise AssertionError('no suitable message within %.1f s' % timeout)
                self._cond.wait(remaining)

    def current_or_next(self, timeout=10.0, condition=lambda m: True):
        """The latest message if it satisfies condition (latched topics), else the next one."""
        with self._cond:
            if self.msg is not None and condition(self.msg):
                return self.msg
        return self.next(timeout, condition)

    def close(self):
        self.sub.unregister()


def stats_listener():
    return Latest(NODE + '/stats', SimulationStats)


def cloud_listener():
    return Latest(NODE + '/particles', PointCloud2)


def cloud_points(cloud):
    """List of (x, y, z, vx, vy, vz, density, speed) tuples of a pbf_node cloud."""
    n = cloud.width * cloud.height
    fmt = '<' + 'f' * (cloud.point_step // 4)
    return [struct.unpack_from(fmt, cloud.data, i * cloud.point_step) for i in range(n)]


def mean(values):
    values = list(values)
    return sum(values) / len(values)
