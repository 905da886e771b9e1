"""Helpers shared by the pbf_node rostest nodes."""
import os
import struct
import threading
import time
from xmlrpc.client import ServerProxy

import rosgraph
import rospy
from pbf_ros.msg import SimulationStats
from sensor_msgs.msg import PointCloud2

NODE = '/fluid'
# The node's health on /diagnostics (diagnostic_updater names it '<node>: <task>').
SIMULATION = NODE[1:] + ': simulation'


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
                    raise AssertionError(self._nothing_suitable(timeout))
                self._cond.wait(remaining)

    def settled(self, key, timeout=10.0):
        """Waits for two consecutive messages (arriving after this call) with the same key
        and returns the later: e.g. key=step_count after ~pause returns. Messages published
        before the service took effect may still be on their way; the first of them is not
        the paused state."""
        deadline = time.time() + timeout
        with self._cond:
            start = self.count
            previous = None
            while True:
                if self.count > start:
                    if previous is not None and self.count > previous[0] and \
                            key(self.msg) == previous[1]:
                        return self.msg
                    if previous is None or self.count > previous[0]:
                        previous = (self.count, key(self.msg))
                remaining = deadline - time.time()
                if remaining <= 0:
                    raise AssertionError('no two consecutive messages agreed within %.1f s' %
                                         timeout)
                self._cond.wait(remaining)

    def current_or_next(self, timeout=10.0, condition=lambda m: True):
        """The latest message if it satisfies condition (latched topics), else the next one
        that does. One lock throughout: a message arriving between the look at the latest
        and the wait is still seen (a latched topic may never publish again)."""
        deadline = time.time() + timeout
        with self._cond:
            checked = None  # the count whose message has been checked
            while True:
                if self.msg is not None and self.count != checked:
                    if condition(self.msg):
                        return self.msg
                    checked = self.count
                remaining = deadline - time.time()
                if remaining <= 0:
                    raise AssertionError(self._nothing_suitable(timeout))
                self._cond.wait(remaining)

    def connected(self, timeout=10.0):
        """Waits for a latched topic's current message: the connection is then open, so a
        change made next travels over it instead of racing the connection's set-up (the
        node publishes a one-off change of a latched topic once)."""
        return self.current_or_next(timeout)

    def _nothing_suitable(self, timeout):
        """What a timed-out wait saw, for the failure message."""
        return 'no suitable message on %s within %.1f s (%d received, the latest %s)' % (
            self.sub.resolved_name, timeout, self.count,
            'none' if self.msg is None else repr(self.msg)[:400])

    def close(self):
        self.sub.unregister()


def _publisher_has(node_uri, topic, caller_id):
    """Whether the node at node_uri lists an outbound connection on topic to caller_id
    (the slave API's getBusInfo, as rosnode info reads it)."""
    code, _, connections = ServerProxy(node_uri).getBusInfo(caller_id)
    # Each: [connection id, destination caller id, direction, transport, topic, ...].
    return code == 1 and any(len(c) >= 5 and c[1] == caller_id and c[2] == 'o' and c[4] == topic
                             for c in connections)


def wait_connected(subscriber, node=NODE, timeout=10.0):
    """Waits until `subscriber` has a connection to `node`'s publisher of its topic, as both
    ends see it. A subscription is wired up some time after it is made: a line the node logs
    to /rosout right after (e.g. on a ~reset the test calls next) would otherwise be missed.
    The publisher's side is checked too: once (session 30, a loaded host) a /rosout line was
    missed although this subscriber already counted the connection."""
    master = rosgraph.Master(rospy.get_name())
    deadline = time.time() + timeout
    while True:
        try:  # the node may not be up yet
            uri = master.lookupNode(node)
            if (subscriber.impl.has_connection(uri) and
                    _publisher_has(uri, subscriber.resolved_name, rospy.get_name())):
                return
        except (rosgraph.MasterError, OSError):
            pass
        if time.time() > deadline:
            raise AssertionError('%s is not connected to %s within %.1f s' %
                                 (subscriber.resolved_name, node, timeout))
        time.sleep(0.02)


def stats_listener():
    return Latest(NODE + '/stats', SimulationStats)


def cloud_listener():
    return Latest(NODE + '/particles', PointCloud2)


def cloud_points(cloud):
    """List of (x, y, z, vx, vy, vz, density, speed) tuples of a pbf_node cloud."""
    n = cloud.width * cloud.height
    return [struct.unpack_from('<8f', cloud.data, i * cloud.point_step) for i in range(n)]


def cloud_ids(cloud):
    """The particle ids (uint32 field 'id') of a pbf_node cloud, in point order."""
    offset = next(f.offset for f in cloud.fields if f.name == 'id')
    n = cloud.width * cloud.height
    return [struct.unpack_from('<I', cloud.data, i * cloud.point_step + offset)[0] for i in range(n)]


def mean(values):
    values = list(values)
    return sum(values) / len(values)


def node_pid():
    """The process of this test's pbf_node (named `fluid`)."""
    for entry in os.listdir('/proc'):
        if not entry.isdigit():
            continue
        try:
            with open('/proc/%s/cmdline' % entry, 'rb') as f:
                args = f.read().split(b'\0')
        except OSError:
            continue
        if any(a.endswith(b'/pbf_node') for a in args) and b'__name:=fluid' in args:
            return int(entry)
    raise AssertionError('no pbf_node process named fluid')
