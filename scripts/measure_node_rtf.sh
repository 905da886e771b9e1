#!/bin/bash
# The node's real-time factor on the default scene as fast as it can run
# (real_time_factor:=0), in three set-ups, one after the other (README "Performance"):
#   headless   nothing subscribed but ~stats
#   cloud      ~particles subscribed (rostopic hz: receives every message, does not parse it)
#   surface    ~particles and the rendered colour image subscribed
# Each: launch, wait WARMUP s, then measure_rtf.py over SECONDS s, then shut down.
#
#   scripts/measure_node_rtf.sh [--warmup S] [--seconds S] [--only "headless cloud surface"]
#                               [--node-bin BIN --params YAML] [--image-topic T]
#
# --node-bin runs another build's pbf_node binary instead of this package's (e.g. the
# baseline's, built by scripts/bench_vs_baseline.sh's recipe with
# `make pbf_node pbf_ros_generate_messages_py`) under its own roscore, with the parameters of
# YAML (that build's config/fluid_defaults.yaml) and OMP_WAIT_POLICY=passive, as the
# baseline's fluid.launch ran it; its ~stats are read with that build's message definition. --image-topic:
# the colour image to subscribe (default /fluid/rgb/image_rect_color; the baseline e7d8d7f
# called it /fluid/surface/image_raw).
# Needs the workspace built (scripts/build.sh) and no other ROS master on the default port.
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WARMUP=10
SECONDS_MEASURED=20
ONLY="headless cloud surface"
NODE_BIN=""
PARAMS=""
IMAGE_TOPIC=/fluid/rgb/image_rect_color
while [ $# -gt 0 ]; do
  case "$1" in
    --warmup) WARMUP="$2"; shift ;;
    --seconds) SECONDS_MEASURED="$2"; shift ;;
    --only) ONLY="$2"; shift ;;
    --node-bin) NODE_BIN="$2"; shift ;;
    --params) PARAMS="$2"; shift ;;
    --image-topic) IMAGE_TOPIC="$2"; shift ;;
    -h|--help) sed -n '2,19p' "$0"; exit 0 ;;
    *) echo "measure_node_rtf.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
# The workspace's setup script reads unset variables (ROS_DISTRO): source it without -u.
set +u
# shellcheck disable=SC1091
source "$ROOT/build/devel/setup.bash"
set -u
LOG="$ROOT/build/measure_node_rtf"
mkdir -p "$LOG"

PIDS=()
stop_all() {
  for p in "${PIDS[@]}"; do kill -INT "$p" 2> /dev/null || true; done
  for p in "${PIDS[@]}"; do wait "$p" 2> /dev/null || true; done
  PIDS=()
}
trap stop_all EXIT

start_node() {  # $1: set-up name (for the log)
  if [ -z "$NODE_BIN" ]; then
    roslaunch pbf_ros fluid.launch real_time_factor:=0 output:=log > "$LOG/$1.launch.log" 2>&1 &
    PIDS+=($!)
    return
  fi
  roscore > "$LOG/$1.roscore.log" 2>&1 &
  PIDS+=($!)
  for _ in $(seq 1 30); do rosparam list > /dev/null 2>&1 && break; sleep 1; done
  rosparam load "$PARAMS" /fluid
  rosparam set /fluid/scene dam_break
  rosparam set /fluid/real_time_factor 0
  # Its own libraries first: this workspace's setup put ours on LD_LIBRARY_PATH.
  local libs
  libs="$(dirname "$(dirname "$NODE_BIN")")"
  LD_LIBRARY_PATH="$libs:${LD_LIBRARY_PATH:-}" OMP_WAIT_POLICY=passive "$NODE_BIN" __name:=fluid \
    > "$LOG/$1.node.log" 2>&1 &
  PIDS+=($!)
}

for setup in $ONLY; do
  start_node "$setup"
  # Wait for the node's statistics, then subscribe what the set-up asks for.
  for _ in $(seq 1 60); do
    rostopic list 2> /dev/null | grep -q '^/fluid/stats$' && break
    sleep 1
  done
  if [ "$setup" != headless ]; then
    rostopic hz /fluid/particles > "$LOG/$setup.cloud_hz.log" 2>&1 &
    PIDS+=($!)
  fi
  if [ "$setup" = surface ]; then
    rostopic hz "$IMAGE_TOPIC" > "$LOG/$setup.image_hz.log" 2>&1 &
    PIDS+=($!)
  fi
  sleep "$WARMUP"
  echo -n "$setup: "
  if [ -n "$NODE_BIN" ]; then
    PYTHONPATH="$(dirname "$(dirname "$NODE_BIN")")/python3/dist-packages:${PYTHONPATH:-}" \
      rosrun pbf_ros measure_rtf.py "$SECONDS_MEASURED" /fluid
  else
    rosrun pbf_ros measure_rtf.py "$SECONDS_MEASURED" /fluid
  fi
  # The node first, then its master (stop_all signals in start order: roscore first).
  for ((k = ${#PIDS[@]} - 1; k >= 0; k--)); do kill -INT "${PIDS[$k]}" 2> /dev/null || true; done
  stop_all
  sleep 2
done
