#!/usr/bin/python3
"""Run by test/install_space.sh in the install's environment: the node started by
`roslaunch pbf_ros fluid.launch` runs the installed pbf_node with the installed libraries,
publishes stats (pbf_ros.msg imported from the install) and renders a depth image with the
installed shaders of the installed scene.
  check_installed_node.py PREFIX"""
import os
import sys
import time
import xmlrpc.client

import rosgraph
import rospy
from sensor_msgs.msg import Image

NODE = '/fluid'


def wait_for(what, timeout, get):
    deadline = time.time() + timeout
    while time.time() < deadline:
        value = get()
        if value:
            return value
        time.sleep(0.1)
    sys.exit('check_installed_node: timed out after %.0f s waiting for %s' % (timeout, what))


def main(prefix):
    import pbf_ros.msg  # the installed message module
    if not os.path.realpath(pbf_ros.msg.__file__).startswith(os.path.realpath(prefix)):
        sys.exit('pbf_ros.msg comes from %s, not the install' % pbf_ros.msg.__file__)
    master = rosgraph.Master('/check_installed_node')
    wait_for('the ROS master', 30.0, master.is_online)
    rospy.init_node('check_installed_node')

    stats = []
    sub = rospy.Subscriber(NODE + '/stats', pbf_ros.msg.SimulationStats, stats.append)
    wait_for('%s/stats' % NODE, 40.0, lambda: len(stats) >= 2)
    sub.unregister()
    if stats[-1].particle_count < 100:
        sys.exit('stats report %d particles' % stats[-1].particle_count)
    # ROS_PACKAGE_PATH holds only the install: the scene came from it (or the node would
    # not have started), and so must the shaders for a depth image.
    depth = []
    sub = rospy.Subscriber(NODE + '/depth_registered/image_rect', Image, depth.append)
    wait_for('a depth image (shaders from the install)', 40.0, lambda: depth)
    sub.unregister()

    uri = master.lookupNode(NODE)
    code, _, pid = xmlrpc.client.ServerProxy(uri).getPid('/check_installed_node')
    if code != 1:
        sys.exit('cannot get the pid of %s' % NODE)
    real_prefix = os.path.realpath(prefix)
    exe = os.path.realpath('/proc/%d/exe' % pid)
    if not exe.startswith(real_prefix):
        sys.exit('%s runs %s, not the installed pbf_node' % (NODE, exe))
    with open('/proc/%d/maps' % pid) as f:
        ours = {line.split()[-1] for line in f if 'libpbf_' in line}
    if not ours or any(not os.path.realpath(p).startswith(real_prefix) for p in ours):
        sys.exit('%s maps pbf libraries from outside the install: %s' % (NODE, sorted(ours)))
    print('check_installed_node: %s runs %s with %s; %d stats, depth %dx%d' % (
        NODE, exe, sorted(os.path.basename(p) for p in ours), len(stats), depth[0].width,
        depth[0].height))


if __name__ == '__main__':
    main(sys.argv[1])
