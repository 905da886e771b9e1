#!/bin/bash
# README command 1: set up everything, build, and launch the default scene (dam break)
# with pbf_node. Extra arguments go to roslaunch, e.g.  scripts/demo.sh rviz:=true
set -eo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$ROOT/scripts/build.sh"
export PATH=/usr/bin:/bin:$PATH
# shellcheck disable=SC1091
source "${PBF_BUILD_DIR:-$ROOT/build}/devel/setup.bash"
echo "[pbf_ros] launching: roslaunch pbf_ros fluid.launch $*  (Ctrl-C to stop)"
exec roslaunch pbf_ros fluid.launch "$@"
