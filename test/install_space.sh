#!/bin/bash
# ctest test_install_space: installs this build into a temporary directory and runs
# `roslaunch pbf_ros fluid.launch` from there alone: the environment comes from the install's
# setup.bash only (no devel space; ROS_PACKAGE_PATH is the install's share/, so the source
# tree is not found), and check_installed_node.py asserts that the running node, its
# libraries, message modules, shaders and scene all come from the install.
#   test/install_space.sh BUILD_DIR
set -euo pipefail
BUILD="$1"
SRC="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
TMP="$(mktemp -d /tmp/pbf_install_test.XXXXXX)"
LAUNCH_PID=""
cleanup() {
  if [ -n "$LAUNCH_PID" ] && kill -0 "$LAUNCH_PID" 2>/dev/null; then
    kill -INT "$LAUNCH_PID" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$LAUNCH_PID" 2>/dev/null || break; sleep 0.2; done
    kill -KILL "$LAUNCH_PID" 2>/dev/null || true
  fi
  rm -rf "$TMP"
}
trap cleanup EXIT

# Staged with DESTDIR, the way a package is built: catkin gives its setup files an absolute
# destination (the configured CMAKE_INSTALL_PREFIX), which `cmake --install --prefix` would
# not move. The install is relocatable: setup.bash finds its own directory.
INSTALL_PREFIX="$(sed -n 's/^CMAKE_INSTALL_PREFIX:PATH=//p' "$BUILD/CMakeCache.txt")"
PREFIX="$TMP/root$INSTALL_PREFIX"
echo "[install_space] DESTDIR=$TMP/root cmake --install $BUILD  ->  $PREFIX"
DESTDIR="$TMP/root" cmake --install "$BUILD" > "$TMP/install.log" 2>&1 || {
  cat "$TMP/install.log"; exit 1; }
if grep -v "$TMP/root" "$TMP/install.log" | grep -q "^-- \(Installing\|Up-to-date\)"; then
  echo "[install_space] files installed outside the staging directory:"; cat "$TMP/install.log"
  exit 1
fi
for f in setup.bash lib/pbf_ros/pbf_node lib/libpbf_core.so lib/libpbf_fluid_nodelet.so \
         share/pbf_ros/package.xml share/pbf_ros/nodelet_plugins.xml \
         share/pbf_ros/launch/fluid.launch share/pbf_ros/config/scenes/dam_break.yaml \
         share/pbf_ros/config/pbf.rviz share/pbf_ros/shaders/composite.frag \
         share/pbf_ros/urdf/meshes/cup.stl lib/pbf_ros/move_frame.py \
         lib/pbf_ros/rviz_for_node.py; do
  [ -e "$PREFIX/$f" ] || { echo "[install_space] missing from the install: $f"; exit 1; }
done

PORT="$(/usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("", 0)); print(s.getsockname()[1])')"
cat > "$TMP/params.yaml" <<YAML
particle_spacing: 0.05
render_width: 160
render_height: 120
YAML

# A clean environment: nothing from the caller's devel space or source tree.
env -i HOME="$TMP" PATH=/usr/bin:/bin ROS_HOME="$TMP/ros_home" OMP_WAIT_POLICY=passive \
    OMP_NUM_THREADS=1 LP_NUM_THREADS=1 PREFIX="$PREFIX" PORT="$PORT" SRC="$SRC" TMP="$TMP" \
    bash -c '
  set -eo pipefail
  source "$PREFIX/setup.bash"  # (not under set -u: ROS'"'"'s profile.d scripts are not)
  set -u
  # Only the install (Debian'"'"'s own ROS packages in /usr are found without it).
  export ROS_PACKAGE_PATH="$PREFIX/share"
  export ROS_MASTER_URI="http://localhost:$PORT"
  found="$(rospack find pbf_ros)"
  [ "$found" = "$PREFIX/share/pbf_ros" ] || { echo "rospack finds pbf_ros in $found"; exit 1; }
  roslaunch -p "$PORT" pbf_ros fluid.launch params:="$TMP/params.yaml" \
      > "$TMP/roslaunch.log" 2>&1 &
  echo $! > "$TMP/launch.pid"
  /usr/bin/python3 "$SRC/test/ros/check_installed_node.py" "$PREFIX" || {
    echo "---- roslaunch output ----"; cat "$TMP/roslaunch.log"; exit 1; }
' &
CHECK_PID=$!
# The launch's pid, to stop it whatever the check says.
for _ in $(seq 100); do [ -s "$TMP/launch.pid" ] && break; sleep 0.1; done
LAUNCH_PID="$(cat "$TMP/launch.pid" 2>/dev/null || true)"
wait "$CHECK_PID"
