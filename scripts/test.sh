#!/bin/bash
# README command 2 (and CI): set up everything, build, and run every test through ctest:
# the core, renderer and node unit tests (GoogleTest) and the rostest tests.
set -eo pipefail
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${PBF_BUILD_DIR:-$ROOT/build}"
"$ROOT/scripts/build.sh"
export PATH=/usr/bin:/bin:$PATH
echo "[pbf_ros] building the tests"
make -C "$BUILD" -j"$(nproc)" --no-print-directory tests
# shellcheck disable=SC1091
source "$BUILD/devel/setup.bash"
cd "$BUILD"
# OpenMP threads sleep instead of spinning between parallel loops: rostest runs the node,
# the master and the test nodes side by side on 2 cores, where spinning threads starve the
# others (tests check behaviour, not speed; benchmarks run without this).
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
# rostest needs a writable ROS_HOME for its logs; keep it inside the build tree.
export ROS_HOME="$BUILD/ros_home"
ctest --output-on-failure --timeout 600 "$@"
