#!/usr/bin/python3
"""scripts/rviz_for_node.py fits config/pbf.rviz to a node: every topic under the node's own
name (also in a namespace), the particle size = the spacing, the cloud over TCP, the surface
displays only when asked. No master needed (--spacing, --no-rviz)."""
import os
import subprocess
import sys
import tempfile
import unittest

import yaml

ROOT = os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..')
SCRIPT = os.path.join(ROOT, 'scripts', 'rviz_for_node.py')


def fitted(*args, namespace=None):
    """Runs the script (without rviz) and returns the rviz config it wrote."""
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, 'out.rviz')
        env = dict(os.environ)
        env.pop('ROS_NAMESPACE', None)
        if namespace:
            env['ROS_NAMESPACE'] = namespace
        subprocess.run([sys.executable, SCRIPT, '--no-rviz', '--output', out] + list(args),
                       check=True, env=env, stdout=subprocess.PIPE)
        with open(out) as f:
            text = f.read()
    return text, yaml.safe_load(text)


def displays(config, cls):
    return [d for d in config['Visualization Manager']['Displays'] if d['Class'] == cls]


class RvizForNodeTest(unittest.TestCase):

    def test_topics_follow_the_node_name_and_namespace(self):
        text, config = fitted('--node', 'fluid2', '--spacing', '0.03', '--surface', 'true',
                              namespace='/lab')
        self.assertNotIn('/fluid/', text)
        for d in displays(config, 'rviz/PointCloud2'):
            self.assertEqual(d['Topic'], '/lab/fluid2/particles')
        self.assertEqual(displays(config, 'rviz/MarkerArray')[0]['Marker Topic'],
                         '/lab/fluid2/markers')
        self.assertEqual(displays(config, 'rviz/InteractiveMarkers')[0]['Update Topic'],
                         '/lab/fluid2/obstacle_markers/update')
        for cls in ('rviz/Image', 'rviz/Camera'):
            self.assertEqual(displays(config, cls)[0]['Image Topic'],
                             '/lab/fluid2/rgb/image_rect_color')

    def test_points_are_as_large_as_the_spacing_and_come_over_tcp(self):
        _, config = fitted('--node', '/fluid', '--spacing', '0.035')
        clouds = displays(config, 'rviz/PointCloud2')
        self.assertEqual(len(clouds), 2)
        for d in clouds:
            self.assertAlmostEqual(d['Size (m)'], 0.035)
            self.assertIs(d['Unreliable'], False)

    def test_surface_displays_only_when_asked(self):
        # Not merely unticked: rviz re-enables an image display whose panel it restores.
        for args in ([], ['--surface', 'false']):
            text, config = fitted('--node', '/fluid', '--spacing', '0.02', *args)
            self.assertNotIn('image_rect_color', text)
            self.assertEqual(displays(config, 'rviz/Image') + displays(config, 'rviz/Camera'), [])
            self.assertNotIn('Fluid surface (pbf_node render, ~rgb/image_rect_color)',
                             config['Window Geometry'])
            self.assertEqual(len(displays(config, 'rviz/PointCloud2')), 2)  # the rest stays
        _, config = fitted('--node', '/fluid', '--spacing', '0.02', '--surface', 'true')
        for cls in ('rviz/Image', 'rviz/Camera'):
            d = displays(config, cls)[0]
            self.assertIs(d['Enabled'], True, cls)
            self.assertEqual(d['Image Topic'], '/fluid/rgb/image_rect_color')

    def test_robot_and_wrench_displays_when_asked(self):
        _, config = fitted('--node', 'fluid', '--spacing', '0.01')
        self.assertEqual(displays(config, 'rviz/RobotModel') + displays(config, 'rviz/WrenchStamped'), [])
        _, config = fitted('--node', 'fluid', '--spacing', '0.01', '--robot-description',
                           'robot_description', '--wrench', 'cup', '--wrench', 'container',
                           namespace='/lab')
        robot = displays(config, 'rviz/RobotModel')
        self.assertEqual(len(robot), 1)
        self.assertEqual(robot[0]['Robot Description'], 'robot_description')
        self.assertEqual([d['Topic'] for d in displays(config, 'rviz/WrenchStamped')],
                         ['/lab/fluid/wrench/cup', '/lab/fluid/wrench/container'])

    def test_the_shipped_config_is_already_right_for_the_default_node(self):
        with open(os.path.join(ROOT, 'config', 'pbf.rviz')) as f:
            config = yaml.safe_load(f)
        for d in displays(config, 'rviz/PointCloud2'):
            self.assertEqual(d['Topic'], '/fluid/particles')
            self.assertIs(d['Unreliable'], False)
        for cls in ('rviz/Image', 'rviz/Camera'):
            self.assertEqual(displays(config, cls)[0]['Image Topic'],
                             '/fluid/rgb/image_rect_color')


if __name__ == '__main__':
    unittest.main()
