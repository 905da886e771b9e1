#!/usr/bin/python3
"""Starts rviz on config/pbf.rviz made to fit one pbf_node (or FluidNodelet).

The shipped config is written for the default node /fluid. This fills in the node's own
topics (a node started with another name or in a namespace), sets the particle size to the
running fluid's particle spacing, subscribes to the cloud over TCP (reliable), and keeps the
surface image displays only when asked: rendering the surface for rviz costs the simulation
about half its real-time factor on a small machine (fluid.launch surface:=true lets the
renderer share the CPU; doc/performance.md). They are removed rather than unticked: rviz
1.14 re-enables an image display whose panel its saved window state shows, and subscribes.

  rviz_for_node.py [--node NAME] [--surface true|false] [--spacing METRES]
                   [--robot-description PARAM] [--wrench SOLID ...]
                   [--config IN.rviz] [--output OUT.rviz] [--no-rviz] [rviz args...]

--robot-description adds a RobotModel display of the URDF in PARAM; each --wrench SOLID adds
a Wrench display of the node's ~wrench/SOLID (e.g. a robot link: cup).

OUT.rviz defaults to $ROS_HOME/pbf_ros/rviz_<node>.rviz (~/.ros/...).

NAME is resolved like a node name (relative to ROS_NAMESPACE, which roslaunch sets). The
spacing is read from the node's dynamic_reconfigure parameter `particle_spacing` once the
node's reconfigure service is up (at most --wait seconds), unless --spacing gives it.
"""
import argparse
import math
import os
import sys

import yaml

import rosgraph.names

# The displays of config/pbf.rviz that show the node's topics, by rviz class.
CLOUD = 'rviz/PointCloud2'
MARKERS = 'rviz/MarkerArray'
DRAG = 'rviz/InteractiveMarkers'
SURFACE = ('rviz/Image', 'rviz/Camera')


def resolve_node(name):
    # resolve_name takes a caller (a node name) and resolves relative to its namespace.
    caller = rosgraph.names.ns_join(rosgraph.names.get_ros_namespace(), 'rviz_for_node')
    return rosgraph.names.resolve_name(name, caller)


def fit_config(config, node, spacing, surface):
    """Returns the rviz config (a dict) made to fit `node`; changes `config` in place."""
    manager = config['Visualization Manager']
    displays = manager['Displays']
    surface_names = [d['Name'] for d in displays if d.get('Class') in SURFACE]
    if not surface:
        manager['Displays'] = displays = [d for d in displays if d.get('Class') not in SURFACE]
        for name in surface_names:
            config.get('Window Geometry', {}).pop(name, None)
    for display in displays:
        cls = display.get('Class')
        if cls == CLOUD:
            display['Topic'] = node + '/particles'
            display['Unreliable'] = False  # TCP: a cloud is never half-delivered
            if spacing is not None:
                display['Size (m)'] = float(spacing)
        elif cls == MARKERS:
            display['Marker Topic'] = node + '/markers'
        elif cls == DRAG:
            display['Update Topic'] = node + '/obstacle_markers/update'
        elif cls in SURFACE:
            display['Image Topic'] = node + '/rgb/image_rect_color'
            display['Enabled'] = True
            display['Value'] = True
    return config


def robot_display(param):
    """An rviz RobotModel display of the URDF in parameter `param` (half transparent, so the
    fluid inside the robot's cup shows)."""
    return {'Alpha': 0.6, 'Class': 'rviz/RobotModel', 'Collision Enabled': False,
            'Enabled': True, 'Name': 'Robot (%s)' % param, 'Robot Description': param,
            'TF Prefix': '', 'Update Interval': 0, 'Value': True, 'Visual Enabled': True}


def wrench_display(node, solid):
    """An rviz Wrench display of the node's ~wrench/<solid>: 5 cm of arrow per newton, 2 cm
    wide (rviz hides an arrow shorter than its width: at 0.3, a cup's 2 N would not show)."""
    return {'Accept NaN Values': False, 'Alpha': 1, 'Arrow Width': 0.02,
            'Class': 'rviz/WrenchStamped', 'Enabled': True, 'Force Arrow Scale': 0.05,
            'Force Color': '204; 51; 51', 'History Length': 1,
            'Name': 'Wrench on %s (~wrench/%s)' % (solid, solid), 'Queue Size': 10,
            'Topic': node + '/wrench/' + solid, 'Torque Arrow Scale': 0.5,
            'Torque Color': '204; 204; 51', 'Unreliable': False, 'Value': True}


def add_robot_and_wrenches(config, node, robot_description, wrenches):
    """Appends the RobotModel and Wrench displays asked for; changes `config` in place."""
    displays = config['Visualization Manager']['Displays']
    if robot_description:
        displays.append(robot_display(robot_description))
    for solid in wrenches or []:
        displays.append(wrench_display(node, solid))
    return config


def node_spacing(node, wait):
    """The running node's particle_spacing, or None (with a warning) if it does not come."""
    import rospy  # only when asked to look at a running node
    service = node + '/set_parameters'
    try:
        # The reconfigure server advertises this after it has written every parameter of
        # this run (values a previous run left behind are overwritten by then).
        rospy.wait_for_service(service, timeout=wait)
        return float(rospy.get_param(node + '/particle_spacing'))
    except (rospy.ROSException, KeyError, ValueError) as e:
        sys.stderr.write('rviz_for_node: no particle_spacing from %s (%s); keeping the '
                         "config's particle size\n" % (node, e))
        return None


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--node', default='fluid')
    parser.add_argument('--surface', default='false', choices=['true', 'false'])
    parser.add_argument('--spacing', type=float)
    parser.add_argument('--wait', type=float, default=30.0)
    parser.add_argument('--robot-description', default='',
                        help='parameter holding a URDF to show with a RobotModel display')
    parser.add_argument('--wrench', action='append', metavar='SOLID',
                        help="show the node's ~wrench/SOLID (repeatable)")
    parser.add_argument('--config', help="rviz config to start from (default: the package's pbf.rviz)")
    parser.add_argument('--output')
    parser.add_argument('--no-rviz', action='store_true', help='only write the config')
    args, rest = parser.parse_known_args(argv)
    # Refused by name, not written into the config (a probe's --spacing nan gave 'Size (m): .nan').
    if args.spacing is not None and not (math.isfinite(args.spacing) and 0.0 < args.spacing <= 10.0):
        parser.error('--spacing: expected a particle spacing in (0, 10] m, got %r' % args.spacing)
    if not (math.isfinite(args.wait) and args.wait >= 0.0):
        parser.error('--wait: expected seconds >= 0, got %r' % args.wait)
    if args.config is None:
        # The source tree's, or the installed package's.
        args.config = os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'config', 'pbf.rviz')
        if not os.path.isfile(args.config):
            import rospkg
            args.config = os.path.join(rospkg.RosPack().get_path('pbf_ros'), 'config', 'pbf.rviz')
    elif not os.path.isfile(args.config):
        parser.error('--config: no such file: %s' % args.config)

    node = resolve_node(args.node)
    spacing = args.spacing if args.spacing is not None else node_spacing(node, args.wait)
    with open(args.config) as f:
        config = yaml.safe_load(f)
    fit_config(config, node, spacing, args.surface == 'true')
    add_robot_and_wrenches(config, node, args.robot_description, args.wrench)

    output = args.output
    if output is None:
        # One file per node, rewritten on every launch (rviz reads it once, at start).
        import rospkg
        directory = os.path.join(rospkg.get_ros_home(), 'pbf_ros')
        os.makedirs(directory, exist_ok=True)
        output = os.path.join(directory, 'rviz%s.rviz' % node.replace('/', '_'))
    try:
        with open(output, 'w') as f:
            yaml.safe_dump(config, f, default_flow_style=False, sort_keys=False)
    except OSError as e:
        parser.error('--output: cannot write %s: %s' % (output, e.strerror))
    if args.no_rviz:
        print(output)
        return 0
    # roslaunch's __name/__log remappings go to rviz, which is the node the user sees.
    os.execvp('rviz', ['rviz', '-d', output] + rest)


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
