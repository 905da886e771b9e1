#!/bin/bash
# Installs what is missing, then configures and builds pbf_ros (Release) into ./build.
# Used by demo.sh and test.sh; safe to run again (only changed files rebuild).
set -euo pipefail
# Debian's ROS Python modules live under /usr/bin/python3, not a pyenv shim.
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${PBF_BUILD_DIR:-$ROOT/build}"

"$ROOT/scripts/install_deps.sh"

echo "[pbf_ros] configuring in $BUILD"
# catkin snapshots the environment for tests (catkin_generated/setup_cached.sh) at configure
# time and only lists devel folders that already exist: without these, a first build gives
# rostest an empty PYTHONPATH and the test nodes cannot import pbf_ros.msg.
mkdir -p "$BUILD/devel/lib/python3/dist-packages"
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release > "$BUILD/configure.log" 2>&1 || {
  cat "$BUILD/configure.log"; exit 1; }
echo "[pbf_ros] building (make -j$(nproc))"
make -C "$BUILD" -j"$(nproc)" --no-print-directory "$@"
