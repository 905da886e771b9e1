#!/bin/bash
# Installs the Debian bookworm packages pbf_ros needs, only those that are missing
# (idempotent: a second run installs nothing and does not touch the network).
set -euo pipefail

PACKAGES=(
  # toolchain and libraries of the ROS-free core
  # (libbenchmark-dev only for the pbf_step_benchmark developer tool; optional)
  build-essential cmake libeigen3-dev libyaml-cpp-dev libgtest-dev libbenchmark-dev
  # ROS 1 from Debian (installs into /usr)
  catkin ros-core-dev libroscpp-dev libroslib-dev ros-message-generation ros-message-runtime
  libsensor-msgs-dev libstd-srvs-dev libvisualization-msgs-dev libgeometry-msgs-dev
  libdiagnostic-msgs-dev libdiagnostic-updater-dev python3-diagnostic-msgs
  libtf2-ros-dev libtf2-geometry-msgs-dev python3-tf2-ros
  libdynamic-reconfigure-config-init-mutex-dev python3-dynamic-reconfigure
  libimage-transport-dev librostest-dev python3-rostest python3-rospy python3-roslaunch
  python3-rosmsg python3-sensor-msgs python3-std-srvs python3-rosgraph-msgs rosbash
  python3-rostopic python3-rosservice
  # the nodelet (pbf_ros/FluidNodelet) and the `nodelet` manager/loader executable; the
  # depth-to-cloud example and its test run depth_image_proc's nodelets beside it (its
  # plugin description is in the -dev package, which brings OpenCV's headers along)
  libnodeletlib-dev libnodeletlib-tools pluginlib-dev libdepth-image-proc-dev
  libinteractive-markers-dev
  # what Debian's rosdep maps package.xml's other keys to, so `rosdep check` stays quiet
  # (librviz-dev is Debian's package for the rviz key; the rviz package below runs rviz)
  librviz-dev python3-visualization-msgs python3-diagnostic-updater python3-tf2-geometry-msgs
  image-transport-tools python3-nodelet ros-tf2-msgs
  # robots as solids: URDF, and meshes through geometric_shapes (assimp); check_urdf
  liburdf-dev libgeometric-shapes-dev liburdfdom-tools
  # ~robot_link_regex: Boost.Regex bounds a match's work (std::regex does not)
  libboost-regex-dev
  # tf for a robot description (robot_solids rostest, robot demos)
  ros-robot-state-publisher
  # headless rendering
  libosmesa6-dev libegl-dev libgl-dev libgles-dev libpng-dev
  # plots, and looking at the demo like a user
  python3-matplotlib python3-numpy python3-yaml rviz xvfb
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "[pbf_ros] all ${#PACKAGES[@]} Debian packages already installed"
  exit 0
fi

echo "[pbf_ros] installing missing Debian packages: ${missing[*]}"
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
