#!/usr/bin/python3
"""pbf_node's surface rendering: nothing is rendered without subscribers; once subscribed,
image, depth and camera_info arrive with one header in fluid_camera_optical; K agrees with
the image; the camera frame is on tf and looks at the container; a render-only reconfigure
changes the image and leaves the simulation alone; a paused fluid is not rendered over and
over; a camera position set by hand replaces the automatic camera."""
import copy
import math
import os
import struct
import subprocess
import threading
import time
import unittest

import dynamic_reconfigure.client
import rospy
import rostest
from diagnostic_msgs.msg import DiagnosticArray
from sensor_msgs.msg import CameraInfo, Image
from std_srvs.srv import SetBool
from tf2_msgs.msg import TFMessage

from fluid_test_util import NODE, SIMULATION, Latest, node_pid, stats_listener

WIDTH, HEIGHT = 160, 120
FRAME = 'fluid_camera_optical'
# An RGB-D camera's layout, as depth_image_proc's point_cloud_xyzrgb takes it.
TOPICS = {
    'image': (NODE + '/rgb/image_rect_color', Image),
    'info': (NODE + '/rgb/camera_info', CameraInfo),
    'depth': (NODE + '/depth_registered/image_rect', Image),
    'depth_info': (NODE + '/depth_registered/camera_info', CameraInfo),
}


class ByStamp:
    """Subscribes to the surface topics and groups their messages by header stamp."""

    def __init__(self):
        self._cond = threading.Condition()
        self.messages = {}  # stamp -> {name: msg}
        self.subs = [rospy.Subscriber(topic, msg_type, self._callback, callback_args=name,
                                      queue_size=5)
                     for name, (topic, msg_type) in TOPICS.items()]

    def _callback(self, msg, name):
        with self._cond:
            self.messages.setdefault(msg.header.stamp, {})[name] = msg
            self._cond.notify_all()

    def complete_set(self, timeout, condition=lambda group: True):
        """Waits for a stamp that all topics carried (and satisfies condition)."""
        deadline = time.time() + timeout
        with self._cond:
            while True:
                for stamp in sorted(self.messages):
                    group = self.messages[stamp]
                    if len(group) == len(TOPICS) and condition(group):
                        return stamp, group
                remaining = deadline - time.time()
                if remaining <= 0:
                    raise AssertionError('no image + depth + camera_infos with one stamp within '
                                         '%.1f s (stamps: %s)' % (
                                             timeout, {s.to_sec(): sorted(g) for s, g in
                                                       self.messages.items()}))
                self._cond.wait(remaining)

    def close(self):
        for sub in self.subs:
            sub.unregister()


def depth_values(msg):
    return struct.unpack(('>' if msg.is_bigendian else '<') + 'f' * (msg.width * msg.height),
                         msg.data)


def rotate(q, v):
    """Rotates v by the unit quaternion q = (x, y, z, w)."""
    x, y, z, w = q
    # v' = v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)
    ux = (y * v[2] - z * v[1], z * v[0] - x * v[2], x * v[1] - y * v[0])
    uux = (y * ux[2] - z * ux[1], z * ux[0] - x * ux[2], x * ux[1] - y * ux[0])
    return tuple(v[i] + 2.0 * w * ux[i] + 2.0 * uux[i] for i in range(3))


class SurfaceTopicsTest(unittest.TestCase):

    def test_01_no_subscriber_means_no_render_work(self):
        stats = stats_listener()
        try:
            # Let the node start, then watch for a while: nobody subscribes to the images.
            stats.next(timeout=30.0)
            first = stats.next(timeout=10.0)
            time.sleep(2.0)
            last = stats.next(timeout=10.0)
            for m in (first, last):
                self.assertIn('surface', m.skipped_stages)
                self.assertEqual(m.time_render_ms, 0.0)
                self.assertEqual(m.surface_frames, 0)
            self.assertGreater(last.step_count, first.step_count)  # the fluid runs meanwhile
        finally:
            stats.close()

    def test_02_image_depth_and_camera_info_share_one_header(self):
        surface = ByStamp()
        stats = stats_listener()
        try:
            stamp, group = surface.complete_set(timeout=25.0)
            image, info, depth = group['image'], group['info'], group['depth']
            # One camera: the depth image's camera_info is the colour image's. Not the
            # sequence number: roscpp counts it per topic and only while someone subscribes,
            # and this test's two subscriptions may connect a frame apart.
            depth_info = copy.deepcopy(group['depth_info'])
            depth_info.header.seq = info.header.seq
            self.assertEqual(depth_info, info)
            for m in (image, info, depth):
                self.assertEqual(m.header.frame_id, FRAME)
                self.assertEqual(m.header.stamp, stamp)
            self.assertEqual(image.encoding, 'rgb8')
            self.assertEqual((image.width, image.height), (WIDTH, HEIGHT))
            self.assertEqual(image.step, WIDTH * 3)
            self.assertEqual(len(image.data), HEIGHT * image.step)

            self.assertEqual(depth.encoding, '32FC1')
            self.assertEqual((depth.width, depth.height), (WIDTH, HEIGHT))
            self.assertEqual(depth.step, WIDTH * 4)
            values = depth_values(depth)
            finite = [v for v in values if math.isfinite(v)]
            nan = [v for v in values if math.isnan(v)]
            self.assertGreater(len(finite), 50, 'fluid pixels')
            self.assertGreater(len(nan), 50, 'no-fluid pixels are NaN')
            self.assertEqual(len(finite) + len(nan), len(values))  # no inf
            self.assertTrue(all(0.02 < v < 20.0 for v in finite), 'metres in front of the camera')

            self.assertEqual((info.width, info.height), (WIDTH, HEIGHT))
            fx, cx, fy, cy = info.K[0], info.K[2], info.K[4], info.K[5]
            self.assertGreater(fx, 0.0)
            self.assertAlmostEqual(fx, fy)
            self.assertAlmostEqual(cx, (WIDTH - 1) / 2.0)
            self.assertAlmostEqual(cy, (HEIGHT - 1) / 2.0)
            self.assertEqual(info.K[8], 1.0)
            self.assertEqual(list(info.P[:3]) + list(info.P[4:7]),
                             [fx, 0.0, cx, 0.0, fy, cy])

            # While someone listens, the stats show the frames and their cost.
            m = stats.next(timeout=10.0, condition=lambda m: 'surface' not in m.skipped_stages
                           and m.surface_frames > 0)
            self.assertGreater(m.time_render_ms, 0.0)
        finally:
            surface.close()
            stats.close()

    def test_02b_render_threads_yield_the_cpu_to_the_solver(self):
        # ~render_idle_priority (default): the render thread and the GL threads it started
        # run at SCHED_IDLE; the node's other threads (the solver's) do not.
        surface = ByStamp()
        try:
            surface.complete_set(timeout=25.0)  # the renderer is up and has drawn
            pid = node_pid()
            policies = {}
            for tid in os.listdir('/proc/%d/task' % pid):
                with open('/proc/%d/task/%s/comm' % (pid, tid)) as f:
                    policies.setdefault(f.read().strip(), []).append(os.sched_getscheduler(int(tid)))
            self.assertIn('pbf_render', policies, 'the render thread is named')
            render = [n for n in policies if n == 'pbf_render' or n.startswith('llvmpipe')]
            for name in render:
                self.assertEqual(set(policies[name]), {os.SCHED_IDLE}, name)
            self.assertEqual(policies['pbf_node'][0], os.SCHED_OTHER, 'the main thread')
        finally:
            surface.close()

    def test_03_camera_frame_on_tf_looks_at_the_container(self):
        tf_static = Latest('/tf_static', TFMessage)
        try:
            m = tf_static.current_or_next(timeout=10.0, condition=lambda m: any(
                t.child_frame_id == FRAME for t in m.transforms))
            t = [t for t in m.transforms if t.child_frame_id == FRAME][0]
            self.assertEqual(t.header.frame_id, 'fluid_domain')
            tr, rot = t.transform.translation, t.transform.rotation
            q = (rot.x, rot.y, rot.z, rot.w)
            # dam_break's container is [0, 1.6] x [0, 0.5] x [0, 0.8]; the automatic camera
            # looks at its centre from above.
            centre = (0.8, 0.25, 0.4)
            to_centre = tuple(centre[i] - p for i, p in enumerate((tr.x, tr.y, tr.z)))
            forward = rotate(q, (0.0, 0.0, 1.0))   # optical z
            down = rotate(q, (0.0, 1.0, 0.0))      # optical y
            norm = math.sqrt(sum(c * c for c in to_centre))
            cos = sum(forward[i] * to_centre[i] for i in range(3)) / norm
            self.assertGreater(cos, 0.999)
            self.assertLess(down[2], 0.0)  # image down points down in the world
            self.assertGreater(tr.z, centre[2])
        finally:
            tf_static.close()

    def test_04_render_reconfigure_changes_the_image_not_the_simulation(self):
        client = dynamic_reconfigure.client.Client(NODE, timeout=20.0)
        stats = stats_listener()
        surface = ByStamp()
        try:
            before = stats.next(timeout=10.0)
            client.update_configuration({'render_width': 120, 'render_height': 90,
                                         'render_filter': 'bilateral'})
            _, group = surface.complete_set(
                timeout=20.0, condition=lambda g: g['image'].width == 120)
            self.assertEqual(group['image'].height, 90)
            self.assertEqual(group['depth'].width, 120)
            self.assertEqual(group['info'].width, 120)
            self.assertAlmostEqual(group['info'].K[2], (120 - 1) / 2.0)
            after = stats.next(timeout=10.0)
            # No reset: the simulation went on.
            self.assertGreater(after.sim_time, before.sim_time)
            self.assertGreater(after.step_count, before.step_count)
        finally:
            client.update_configuration({'render_width': WIDTH, 'render_height': HEIGHT,
                                         'render_filter': 'narrow_range'})
            surface.close()
            stats.close()

    def test_04b_a_faster_render_rate_takes_effect_at_once(self):
        # At render_rate 0.1 the next frame is 10 s away. Raising the rate must not wait for
        # it (it did: the render thread and the snapshots both kept the old period).
        client = dynamic_reconfigure.client.Client(NODE, timeout=20.0)
        images = Latest(NODE + '/rgb/image_rect_color', Image)
        try:
            client.update_configuration({'render_rate': 0.1})
            images.next(timeout=20.0)  # the frame of the new setting (or of this newcomer)
            images.next(timeout=20.0)  # ... and whichever came with it: now 10 s to the next
            start = time.time()
            client.update_configuration({'render_rate': 10.0})
            images.next(timeout=20.0)
            images.next(timeout=20.0)  # a second one, at the new rate
            self.assertLess(time.time() - start, 8.0)
        finally:
            client.update_configuration({'render_rate': 10.0})
            images.sub.unregister()

    def test_05_paused_fluid_is_not_rendered_again_but_newcomers_get_a_frame(self):
        pause = rospy.ServiceProxy(NODE + '/pause', SetBool)
        pause.wait_for_service(timeout=10.0)
        surface = ByStamp()
        stats = stats_listener()
        try:
            surface.complete_set(timeout=20.0)
            self.assertTrue(pause(True).success)
            # Paused once the step counter stands still. The frame of the paused state may
            # still be on its way, for longer on a loaded machine (the render thread runs at
            # idle priority): wait until the frame count stands still for 1.5 s, then check
            # that it stays so.
            stats.settled(key=lambda m: m.step_count, timeout=10.0)
            deadline = time.time() + 15.0
            frames = stats.next(timeout=10.0).surface_frames
            while True:
                time.sleep(1.5)
                now = stats.next(timeout=10.0).surface_frames
                if now == frames:
                    break
                self.assertLess(time.time(), deadline,
                                'a paused fluid is rendered once, not again and again')
                frames = now
            time.sleep(1.5)
            self.assertEqual(stats.next(timeout=10.0).surface_frames, frames,
                             'a paused fluid is rendered once, not again and again')
            # Someone who subscribes now still gets the (paused) surface. Another process:
            # rospy would share this process's connection and never connect anew.
            out = subprocess.run(['rostopic', 'echo', '-n', '1', NODE + '/rgb/image_rect_color/header'],
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=20.0,
                                 check=False, universal_newlines=True)
            self.assertEqual(out.returncode, 0, out.stdout)
            self.assertIn(FRAME, out.stdout)
        finally:
            pause(False)
            surface.close()
            stats.close()

    def test_06_moving_the_camera_turns_the_automatic_camera_off_and_moves_the_frame(self):
        client = dynamic_reconfigure.client.Client(NODE, timeout=20.0)
        tf_static = Latest('/tf_static', TFMessage)
        try:
            tf_static.connected()
            config = client.update_configuration({'camera_position_x': 3.0,
                                                  'camera_position_y': 0.25,
                                                  'camera_position_z': 0.4,
                                                  'camera_look_at_x': 0.0,
                                                  'camera_look_at_y': 0.25,
                                                  'camera_look_at_z': 0.4})
            self.assertFalse(config['camera_auto'])

            def moved(m):
                return any(t.child_frame_id == FRAME and
                           abs(t.transform.translation.x - 3.0) < 1e-6 for t in m.transforms)
            m = tf_static.current_or_next(timeout=10.0, condition=moved)
            t = [t for t in m.transforms if t.child_frame_id == FRAME][0]
            r = t.transform.rotation
            forward = rotate((r.x, r.y, r.z, r.w), (0.0, 0.0, 1.0))
            self.assertAlmostEqual(forward[0], -1.0, places=5)  # looking along -x
            # The fluid frame is still there (one latched /tf_static for both).
            self.assertTrue(any(t.child_frame_id == 'fluid_domain' for t in m.transforms))
        finally:
            client.update_configuration({'camera_auto': True})
            tf_static.close()

    def test_06b_scene_change_reframes_the_automatic_camera(self):
        client = dynamic_reconfigure.client.Client(NODE, timeout=20.0)
        tf_static = Latest('/tf_static', TFMessage)
        try:
            tf_static.connected()
            config = client.update_configuration({'camera_auto': True,
                                                  'scene': 'hydrostatic_tank'})
            self.assertTrue(config['camera_auto'])
            centre = (0.2, 0.2, 0.3)  # hydrostatic_tank: [0, 0.4] x [0, 0.4] x [0, 0.6]

            def looks_at_centre(m):
                for t in m.transforms:
                    if t.child_frame_id != FRAME:
                        continue
                    tr, r = t.transform.translation, t.transform.rotation
                    to_centre = [centre[i] - p for i, p in enumerate((tr.x, tr.y, tr.z))]
                    norm = math.sqrt(sum(c * c for c in to_centre))
                    forward = rotate((r.x, r.y, r.z, r.w), (0.0, 0.0, 1.0))
                    return sum(forward[i] * to_centre[i] for i in range(3)) / norm > 0.999
                return False
            tf_static.current_or_next(timeout=10.0, condition=looks_at_centre)
        finally:
            client.update_configuration({'scene': 'dam_break'})
            tf_static.close()

    def test_07_unsubscribed_means_rendering_stops(self):
        stats = stats_listener()
        try:
            # The subscribers of the earlier tests are gone; give the node a moment to notice.
            m = stats.next(timeout=10.0, condition=lambda m: 'surface' in m.skipped_stages)
            frames = m.surface_frames
            time.sleep(2.0)
            m = stats.next(timeout=10.0)
            self.assertIn('surface', m.skipped_stages)
            self.assertEqual(m.surface_frames, frames)
            self.assertEqual(m.time_render_ms, 0.0)
        finally:
            stats.close()

    def test_08_diagnostics_report_the_surface_renderer(self):
        diagnostics = Latest('/diagnostics', DiagnosticArray)
        try:
            m = diagnostics.next(timeout=15.0, condition=lambda m: any(
                s.name == SIMULATION for s in m.status))
            status = [s for s in m.status if s.name == SIMULATION][0]
            values = {kv.key: kv.value for kv in status.values}
            self.assertIn('surface frames rendered', values)
            self.assertGreater(int(values['surface frames rendered']), 0)
            self.assertTrue(values['surface rendering'].startswith('idle'), values)
        finally:
            diagnostics.close()


if __name__ == '__main__':
    rospy.init_node('test_surface_topics')
    rostest.rosrun('pbf_ros', 'surface_topics', SurfaceTopicsTest)
