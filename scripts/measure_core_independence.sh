#!/bin/bash
# Do this host's two cores slow each other down? Runs the 1-thread dam break alone, then two
# copies at once, alternately. If a copy beside another takes no longer than one alone, the
# cores share nothing that limits this workload (no SMT siblings, no saturated memory), and
# a 2-thread run that falls short of 2x loses the rest in our own waiting (README
# "Performance", issue 10's target table).
#   scripts/measure_core_independence.sh [rounds] [simulated seconds]
set -euo pipefail
export PATH=/usr/bin:$PATH
here="$(cd "$(dirname "$0")/.." && pwd)"
run_bin="$here/build/devel/lib/pbf_ros/pbf_run"
rounds="${1:-4}"
seconds="${2:-1.0}"
[[ "$rounds" =~ ^[1-9][0-9]*$ ]] || { echo "measure_core_independence.sh: rounds must be a positive integer (got '$rounds')" >&2; exit 2; }
[[ "$seconds" =~ ^[0-9]*\.?[0-9]+$ && ! "$seconds" =~ ^[0.]+$ ]] || { echo "measure_core_independence.sh: simulated seconds must be a number > 0 (got '$seconds')" >&2; exit 2; }
[[ -x "$run_bin" ]] || { echo "no $run_bin: run scripts/build.sh first" >&2; exit 1; }
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
wall() { OMP_NUM_THREADS=1 "$run_bin" dam_break --seconds "$seconds" 2>&1 | awk '/simulated in/ {print $6}'; }
echo "round  alone[s]  beside_another[s] (two copies at once)"
for r in $(seq "$rounds"); do
  alone="$(wall)"
  wall > "$tmp/a" &
  wall > "$tmp/b"
  wait
  echo "$r  $alone  $(cat "$tmp/a") $(cat "$tmp/b")"
done
