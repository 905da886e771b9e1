#!/usr/bin/python3
"""Times pbf_ros/FluidNodelet's unload: loads it into a running manager, lets it run, unloads
it, N times, and prints each unload's wall time (the manager waits that long).

    rosparam load config/fluid_defaults.yaml /fluid
    rosrun nodelet nodelet manager __name:=fluid_manager &
    scripts/measure_nodelet_unload.py [--cycles N] [--run S] [--manager /fluid_manager] [--name /fluid]

Subscribe to /fluid/rgb/image_rect_color meanwhile (rostopic hz) to time it with a frame in
progress. README "As a nodelet" has session 38's figures."""
import argparse
import time

import rospy
from nodelet.srv import NodeletLoad, NodeletUnload


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument('--cycles', type=int, default=6)
    parser.add_argument('--run', type=float, default=1.0, help='wall s between load and unload')
    parser.add_argument('--manager', default='/fluid_manager')
    parser.add_argument('--name', default='/fluid')
    args = parser.parse_args(rospy.myargv()[1:])
    if args.cycles < 1 or not 0.0 <= args.run <= 3600.0:
        parser.error('need --cycles >= 1 and 0 <= --run <= 3600')
    rospy.init_node('measure_nodelet_unload', anonymous=True)
    load = rospy.ServiceProxy(args.manager + '/load_nodelet', NodeletLoad)
    unload = rospy.ServiceProxy(args.manager + '/unload_nodelet', NodeletUnload)
    load.wait_for_service(timeout=30.0)
    times = []
    for _ in range(args.cycles):
        if not load(name=args.name, type='pbf_ros/FluidNodelet', remap_source_args=[],
                    remap_target_args=[], my_argv=[], bond_id='').success:
            raise SystemExit('load_nodelet %s failed' % args.name)
        time.sleep(args.run)
        start = time.time()
        unload(name=args.name)
        times.append(time.time() - start)
        print('unload %.3f s' % times[-1], flush=True)
    times.sort()
    print('unload over %d cycles: min %.3f, median %.3f, max %.3f s'
          % (len(times), times[0], times[len(times) // 2], times[-1]))


if __name__ == '__main__':
    main()
