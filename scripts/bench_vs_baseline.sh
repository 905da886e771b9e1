#!/bin/bash
# Speed against a fixed baseline, measured side by side on this machine (issue 10): builds
# the baseline commit's pbf_step_benchmark in a second folder, this tree's in ./build as
# configured (the shipped default: portable, no -march=native) and, with --native, a third
# build of this tree with -march=native; then runs them alternately, several rounds, so
# that load on a shared machine hits every build alike.
#
#   scripts/bench_vs_baseline.sh [--rounds N] [--native] [--filter REGEX] [--baseline REV]
#   scripts/bench_vs_baseline.sh --dambreak-1m3 [--rounds N] [--seconds S] [--tolerances "T..."]
#                                [--warm-start] [--fast "T..."]
#
#   --rounds N      alternations (default 3); each run is a Google Benchmark with 3 repetitions
#   --native        also build and time this tree with PBF_NATIVE=ON
#   --filter REGEX  benchmark filter (default: the 20k dam-break step, 1 and 2 threads)
#   --baseline REV  baseline commit (default e7d8d7f, the last main before issue 10)
#   --dambreak-1m3  instead of the step benchmark: wall seconds per simulated second of the
#                   1 m^3 dam break (config/scenes/dam_break_1m3.yaml, pbf_run, 2 threads) at
#                   each density tolerance (the average density error each solver iterates
#                   down to; default "0.0005 0.0001"), S simulated seconds (default 1), both
#                   builds with their own shipped defaults otherwise, max_iterations 100
#   --warm-start    (with --dambreak-1m3) also run this tree with warm_start: true ("warm"),
#                   and with that and chebyshev_rho: 0.9 ("warm_cheb")
#   --fast "T..."   (with --dambreak-1m3) also run this tree with the options that make it
#                   fastest at a given error ("fast": FAST_OPTIONS below), asked for the
#                   k-th of these tolerances where the others are asked for the k-th of
#                   --tolerances: the warm-started solve ends below the error asked for, so
#                   the same tolerance is not the same error; the table shows the errors
#
# Baseline recipe: `git worktree add --detach $BASE_DIR/src REV` (BASE_DIR: $PBF_BASELINE_DIR,
# default ~/.cache/pbf_ros/baseline), then a plain Release configure of that tree into
# $BASE_DIR/build and `make pbf_step_benchmark`. The
# baseline's own CMake defaults apply (it built with -march=native).
# Output: build/bench_vs_baseline/<build>_<round>.json and a median table on stdout.
set -euo pipefail
export PATH=/usr/bin:/bin:/usr/sbin:/sbin:$PATH
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
ROUNDS=3
NATIVE=0
WARM=0
FAST_TOLERANCES=""
# Warm start, Chebyshev acceleration for a tall fluid's slow Jacobi solve (rho 0.95), and
# the doubled step validated on the dam break (doc/calibration.md, warm start). Both act on
# the Jacobi solve, which the Gauss-Seidel default replaces (session 21): turned back on.
FAST_OPTIONS="--set gauss_seidel=false --set warm_start=true --set chebyshev_rho=0.95 --set cfl_factor=0.8 --set max_time_step=0.00833333"
FILTER='BM_DamBreakStep/kparticles:20/threads:[12]/boundary:1'
BASELINE=e7d8d7f
MODE=step
SECONDS_SIM=1
TOLERANCES="0.0005 0.0001"
while [ $# -gt 0 ]; do
  case "$1" in
    --rounds|--fast|--filter|--baseline|--seconds|--tolerances)
      if [ $# -lt 2 ] || [ -z "$2" ]; then
        echo "bench_vs_baseline.sh: $1 needs a value (see --help)" >&2; exit 2
      fi ;;
  esac
  case "$1" in
    --rounds) ROUNDS="$2"; shift ;;
    --native) NATIVE=1 ;;
    --warm-start) WARM=1 ;;
    --fast) FAST_TOLERANCES="$2"; shift ;;
    --filter) FILTER="$2"; shift ;;
    --baseline) BASELINE="$2"; shift ;;
    --dambreak-1m3) MODE=dambreak ;;
    --seconds) SECONDS_SIM="$2"; shift ;;
    --tolerances) TOLERANCES="$2"; shift ;;
    -h|--help) sed -n '2,/^# Output:/p' "$0"; exit 0 ;;
    *) echo "bench_vs_baseline.sh: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
  shift
done

if { [ "$WARM" = 1 ] || [ -n "$FAST_TOLERANCES" ]; } && [ "$MODE" != dambreak ]; then
  echo "bench_vs_baseline.sh: --warm-start and --fast need --dambreak-1m3" >&2; exit 2
fi
read -r -a TOL_LIST <<< "$TOLERANCES"
read -r -a FAST_LIST <<< "$FAST_TOLERANCES"
if [ -n "$FAST_TOLERANCES" ] && [ "${#FAST_LIST[@]}" != "${#TOL_LIST[@]}" ]; then
  echo "bench_vs_baseline.sh: --fast needs one tolerance per --tolerances entry (${#TOL_LIST[@]})" >&2; exit 2
fi

# Outside the source tree: a second pbf_ros package below this one would make
# `roslaunch pbf_ros ...` find two of every launch file.
BASE_DIR="${PBF_BASELINE_DIR:-${XDG_CACHE_HOME:-$HOME/.cache}/pbf_ros/baseline}"
OUT="$ROOT/build/bench_vs_baseline"
[ "$MODE" = dambreak ] && OUT="$ROOT/build/bench_dambreak_1m3"
mkdir -p "$BASE_DIR" "$OUT"

# --- builds ---------------------------------------------------------------------------
TOOL=pbf_step_benchmark
[ "$MODE" = dambreak ] && TOOL=pbf_run
"$ROOT/scripts/build.sh" "$TOOL" > "$OUT/build_current.log" 2>&1 || {
  tail -30 "$OUT/build_current.log"; exit 1; }
declare -A BIN
BIN[current]="$ROOT/build/devel/lib/pbf_ros/$TOOL"

if [ ! -d "$BASE_DIR/src" ]; then
  git -C "$ROOT" worktree add --detach "$BASE_DIR/src" "$BASELINE" > /dev/null
fi
git -C "$BASE_DIR/src" checkout --quiet --detach "$BASELINE"
mkdir -p "$BASE_DIR/build/devel/lib/python3/dist-packages"
cmake -S "$BASE_DIR/src" -B "$BASE_DIR/build" -DCMAKE_BUILD_TYPE=Release > "$OUT/build_baseline.log" 2>&1
make -C "$BASE_DIR/build" -j"$(nproc)" "$TOOL" >> "$OUT/build_baseline.log" 2>&1 || {
  tail -30 "$OUT/build_baseline.log"; exit 1; }
BIN[baseline]="$BASE_DIR/build/devel/lib/pbf_ros/$TOOL"

if [ "$NATIVE" = 1 ]; then
  N="$ROOT/build/native"
  mkdir -p "$N/devel/lib/python3/dist-packages"
  cmake -S "$ROOT" -B "$N" -DCMAKE_BUILD_TYPE=Release -DPBF_NATIVE=ON > "$OUT/build_native.log" 2>&1
  make -C "$N" -j"$(nproc)" "$TOOL" >> "$OUT/build_native.log" 2>&1 || {
    tail -30 "$OUT/build_native.log"; exit 1; }
  BIN[native]="$N/devel/lib/pbf_ros/$TOOL"
fi

BUILDS="baseline current"
[ "$NATIVE" = 1 ] && BUILDS="$BUILDS native"
declare -A EXTRA=([baseline]="" [current]="" [native]="")
if [ "$WARM" = 1 ]; then
  BIN[warm]="${BIN[current]}"
  BIN[warm_cheb]="${BIN[current]}"
  EXTRA[warm]="--set gauss_seidel=false --set warm_start=true"
  EXTRA[warm_cheb]="--set gauss_seidel=false --set warm_start=true --set chebyshev_rho=0.9"
  BUILDS="$BUILDS warm warm_cheb"
fi
if [ -n "$FAST_TOLERANCES" ]; then
  BIN[fast]="${BIN[current]}"
  EXTRA[fast]="$FAST_OPTIONS"
  BUILDS="$BUILDS fast"
fi
rm -f "$OUT"/*.json "$OUT"/*.txt

# --- alternating runs -----------------------------------------------------------------
# Sleep-waiting OpenMP threads, as the node's launch file uses.
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
bash "$(dirname "$0")/busy_processes.sh" "[bench]"
echo "[bench] load before: $(cut -d' ' -f1-3 /proc/loadavg)"
if [ "$MODE" = dambreak ]; then
  SCENE="$ROOT/config/scenes/dam_break_1m3.yaml"
  for round in $(seq 1 "$ROUNDS"); do
    for k in "${!TOL_LIST[@]}"; do
      tol="${TOL_LIST[$k]}"
      for build in $BUILDS; do
        asked="$tol"
        [ "$build" = fast ] && asked="${FAST_LIST[$k]}"
        # Filed under the tolerance it is compared at; pbf_run's log names what was asked.
        OMP_NUM_THREADS=2 "${BIN[$build]}" "$SCENE" --seconds "$SECONDS_SIM" \
          --set density_tolerance="$asked" --set max_iterations=100 ${EXTRA[$build]} \
          > "$OUT/${build}_tol${tol}_${round}.txt" 2>&1
        echo "[bench] round $round, tolerance $tol: $build done"
      done
    done
  done
  echo "[bench] load after: $(cut -d' ' -f1-3 /proc/loadavg)"
  exec /usr/bin/python3 "$ROOT/scripts/dambreak_table.py" "$OUT" $BUILDS
fi
for round in $(seq 1 "$ROUNDS"); do
  for build in $BUILDS; do
    "${BIN[$build]}" --benchmark_filter="$FILTER" --benchmark_repetitions=3 \
      --benchmark_report_aggregates_only=true --benchmark_format=json \
      > "$OUT/${build}_${round}.json" 2> /dev/null
    echo "[bench] round $round: $build done"
  done
done
echo "[bench] load after: $(cut -d' ' -f1-3 /proc/loadavg)"
/usr/bin/python3 "$ROOT/scripts/bench_table.py" "$OUT" $BUILDS
