#!/bin/bash
# The node's real-time factor on the default scene as fast as it can run
# (real_time_factor:=0), in up to five set-ups, one after the other (README "Performance"):
#   headless      nothing subscribed but ~stats
#   cloud         ~particles subscribed (rostopic hz: receives every message, does not parse it)
#   surface       ~particles and the rendered colour image subscribed
#   rviz          rviz showing the fluid as a user opens it: `fluid.launch rviz:=true`
#   rviz_surface  the same with the rendered surface shown too (`rviz:=true surface:=true`)
# The rviz set-ups (not run by default) draw on $DISPLAY, or on an Xvfb of their own when
# DISPLAY is unset (rviz renders in software there, as on a machine without a GPU).
# Each: launch, wait WARMUP s, then measure_rtf.py over SECONDS s, then shut down. With
# --sim-window "A B": no warm-up; measure_rtf.py over the simulated interval [A, B] s,
# waiting at most SECONDS s for it (builds of unequal speed compared over the same flow).
#
#   scripts/measure_node_rtf.sh [--warmup S] [--seconds S] [--only "headless cloud surface"]
#                               [--node-bin BIN --params YAML] [--image-topic T]
#                               [--rviz-config RVIZ] [--sim-window "A B"]
#
# --node-bin runs another build's pbf_node binary instead of this package's (e.g. the
# baseline's, built by scripts/bench_vs_baseline.sh's recipe with
# `make pbf_node pbf_ros_generate_messages_py`) under its own roscore, with the parameters of
# YAML (that build's config/fluid_defaults.yaml) and OMP_WAIT_POLICY=passive, as the
# baseline's fluid.launch ran it; its ~stats are read with that build's message definition. --image-topic:
# the colour image to subscribe (default /fluid/rgb/image_rect_color; the baseline e7d8d7f
# called it /fluid/surface/image_raw). --rviz-config (with --node-bin, for the rviz set-ups):
# that build's rviz configuration, opened with plain rviz as its fluid.launch did (the
# baseline's config/pbf.rviz shows the surface image in both rviz set-ups).
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
RVIZ_CONFIG=""
SIM_WINDOW=""
while [ $# -gt 0 ]; do
  case "$1" in
    --warmup|--seconds|--only|--node-bin|--params|--image-topic|--rviz-config|--sim-window)
      if [ $# -lt 2 ] || [ -z "$2" ]; then
        echo "measure_node_rtf.sh: $1 needs a value (see --help)" >&2; exit 2
      fi ;;
  esac
  case "$1" in
    --warmup) WARMUP="$2"; shift ;;
    --seconds) SECONDS_MEASURED="$2"; shift ;;
    --only) ONLY="$2"; shift ;;
    --node-bin) NODE_BIN="$2"; shift ;;
    --params) PARAMS="$2"; shift ;;
    --image-topic) IMAGE_TOPIC="$2"; shift ;;
    --rviz-config) RVIZ_CONFIG="$2"; shift ;;
    --sim-window) SIM_WINDOW="$2"; shift ;;
    -h|--help) sed -n '2,30p' "$0"; exit 0 ;;
    *) echo "measure_node_rtf.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done
if [ -n "$SIM_WINDOW" ] && [ "$(wc -w <<< "$SIM_WINDOW")" != 2 ]; then
  echo "measure_node_rtf.sh: --sim-window needs two simulated times, \"A B\" (got '$SIM_WINDOW')" >&2; exit 2
fi
for setup in $ONLY; do
  case "$setup" in
    headless|cloud|surface) ;;
    rviz|rviz_surface)
      if [ -n "$NODE_BIN" ] && [ -z "$RVIZ_CONFIG" ]; then
        echo "measure_node_rtf.sh: the $setup set-up with --node-bin needs --rviz-config" >&2; exit 2
      fi ;;
    *) echo "measure_node_rtf.sh: unknown set-up '$setup' (headless cloud surface rviz rviz_surface)" >&2; exit 2 ;;
  esac
done
# The workspace's setup script reads unset variables (ROS_DISTRO): source it without -u.
set +u
# shellcheck disable=SC1091
source "$ROOT/build/devel/setup.bash"
set -u
LOG="$ROOT/build/measure_node_rtf"
mkdir -p "$LOG"

status=0  # 1 once a measurement failed (the others still run)
PIDS=()
stop_all() {
  for p in "${PIDS[@]}"; do kill -INT "$p" 2> /dev/null || true; done
  for p in "${PIDS[@]}"; do wait "$p" 2> /dev/null || true; done
  PIDS=()
}

# rviz needs an X display: an Xvfb of our own when there is none (kept to the end).
XVFB_PID=""
ensure_display() {
  [ -n "${DISPLAY:-}" ] && return
  export DISPLAY=:97
  Xvfb "$DISPLAY" -screen 0 1280x1024x24 > "$LOG/xvfb.log" 2>&1 &
  XVFB_PID=$!
  sleep 2
}
trap 'stop_all; [ -z "$XVFB_PID" ] || kill "$XVFB_PID" 2> /dev/null || true' EXIT

start_node() {  # $1: set-up name (for the log)
  local launch_args=()
  case "$1" in
    rviz) ensure_display; launch_args=(rviz:=true) ;;
    rviz_surface) ensure_display; launch_args=(rviz:=true surface:=true) ;;
  esac
  if [ -z "$NODE_BIN" ]; then
    roslaunch pbf_ros fluid.launch real_time_factor:=0 output:=log "${launch_args[@]}" \
      > "$LOG/$1.launch.log" 2>&1 &
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
  if [ "${#launch_args[@]}" -gt 0 ]; then
    rviz -d "$RVIZ_CONFIG" > "$LOG/$1.rviz.log" 2>&1 &
    PIDS+=($!)
  fi
}

bash "$(dirname "$0")/busy_processes.sh" "[rtf]" >&2
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
  measure_args=("$SECONDS_MEASURED" /fluid)
  if [ -n "$SIM_WINDOW" ]; then
    # shellcheck disable=SC2206  # two numbers
    measure_args+=(--sim-window $SIM_WINDOW)
  else
    sleep "$WARMUP"
  fi
  echo -n "$setup: "
  if [ -n "$NODE_BIN" ]; then
    PYTHONPATH="$(dirname "$(dirname "$NODE_BIN")")/python3/dist-packages:${PYTHONPATH:-}" \
      rosrun pbf_ros measure_rtf.py "${measure_args[@]}" || status=1
  else
    rosrun pbf_ros measure_rtf.py "${measure_args[@]}" || status=1
  fi
  # The node first, then its master (stop_all signals in start order: roscore first).
  for ((k = ${#PIDS[@]} - 1; k >= 0; k--)); do kill -INT "${PIDS[$k]}" 2> /dev/null || true; done
  stop_all
  sleep 2
done
exit "$status"
