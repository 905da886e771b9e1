#!/bin/bash
# The one command that regenerates every validation figure (issue 5): builds pbf_bench and
# pbf_stress (via scripts/build.sh), runs the dam break, the settings sweep (hydrostatic +
# Pareto), the scaling study and the stress matrix, then plots everything and compares the
# dam-break fronts across resolutions (scripts/front_compare.py).
#
#   scripts/bench_all.sh [OUT_DIR] [--quick] [--publish]
#
#   OUT_DIR    where CSV, PNG, logs and summary.md go (default: bench_out)
#   --quick    small, short versions of every study (minutes; to check the pipeline)
#   --publish  also copy the PNGs and the summary CSVs into doc/validation/ (the README's)
# Full run: about 30 min on 2 cores (25 min in session 11, before the tank study's finer runs). Exit status 1 when a stress case fails.
set -euo pipefail
export PATH=/usr/bin:/bin:$PATH   # Debian's python3 with matplotlib, not a pyenv shim
ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD="${PBF_BUILD_DIR:-$ROOT/build}"

OUT=bench_out
QUICK=()
STRESS=()
PUBLISH=0
for arg in "$@"; do
  case "$arg" in
    --quick) QUICK=(--quick); STRESS=(--reduced) ;;
    --publish) PUBLISH=1 ;;
    -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
    -*) echo "bench_all.sh: unknown option '$arg' (see --help)" >&2; exit 2 ;;
    *) OUT="$arg" ;;
  esac
done
mkdir -p "$OUT"
OUT="$(cd "$OUT" && pwd)"

"$ROOT/scripts/build.sh" pbf_bench pbf_stress
BIN="$BUILD/devel/lib/pbf_ros"

# Sleep-waiting OpenMP threads, as the node's launch file uses: on a shared machine the
# default spin-waiting makes small steps many times slower and the timings meaningless.
export OMP_WAIT_POLICY="${OMP_WAIT_POLICY:-passive}"
echo "[bench] output in $OUT (OMP_WAIT_POLICY=$OMP_WAIT_POLICY, load: $(cut -d' ' -f1-3 /proc/loadavg))"
bash "$(dirname "$0")/busy_processes.sh" "[bench]"

nice -n 5 "$BIN/pbf_bench" --out "$OUT" "${QUICK[@]}" | tee "$OUT/pbf_bench.log"
stress_status=0
nice -n 5 "$BIN/pbf_stress" --out "$OUT" "${STRESS[@]}" | tee "$OUT/pbf_stress.log" || stress_status=$?
/usr/bin/python3 "$ROOT/scripts/plot_bench.py" "$OUT"
# How far refinement moves the dam-break front (the dt-halved comparison needs a second run:
# doc/validation.md §1).
[ -f "$OUT/dambreak_front.csv" ] && /usr/bin/python3 "$ROOT/scripts/front_compare.py" "$OUT" | tee "$OUT/front_compare.txt"

if [ "$PUBLISH" = 1 ]; then
  DOC="$ROOT/doc/validation"
  mkdir -p "$DOC"
  cp "$OUT"/*.png "$DOC/"
  for f in dambreak_summary sweep scaling stress tank; do
    [ -f "$OUT/$f.csv" ] && cp "$OUT/$f.csv" "$DOC/"
  done
  echo "[bench] published figures and tables to $DOC"
fi
echo "[bench] done: $OUT/summary.md; stress exit status $stress_status"
exit "$stress_status"
