#!/bin/bash
# The node's real-time factor on the default scene as fast as it can run
# (real_time_factor:=0), in three set-ups, one after the other (README "Performance"):
#   headless   nothing subscribed but ~stats
#   cloud      ~particles subscribed (rostopic hz: receives every message, does not parse it)
#   surface    ~particles and the rendered colour image subscribed (surface:=true)
# Each: launch, wait WARMUP s, then measure_rtf.py over SECONDS s, then shut down.
#
#   scripts/measure_node_rtf.sh [--warmup S] [--seconds S] [--only headless|cloud|surface]
#
# Needs the workspace built (scripts/build.sh) and no other ROS master on the default port.
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
WARMUP=10
SECONDS_MEASURED=20
ONLY="headless cloud surface"
while [ $# -gt 0 ]; do
  case "$1" in
    --warmup) WARMUP="$2"; shift ;;
    --seconds) SECONDS_MEASURED="$2"; shift ;;
    --only) ONLY="$2"; shift ;;
    -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
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

for setup in $ONLY; do
  surface=false
  [ "$setup" = surface ] && surface=true
  roslaunch pbf_ros fluid.launch real_time_factor:=0 surface:="$surface" output:=log \
    > "$LOG/$setup.launch.log" 2>&1 &
  PIDS+=($!)
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
    rostopic hz /fluid/rgb/image_rect_color > "$LOG/$setup.image_hz.log" 2>&1 &
    PIDS+=($!)
  fi
  sleep "$WARMUP"
  echo -n "$setup: "
  rosrun pbf_ros measure_rtf.py "$SECONDS_MEASURED" /fluid
  stop_all
  sleep 2
done
