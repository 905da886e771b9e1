#!/bin/bash
# Prints the processes that used more than a tenth of a CPU over one second, for the
# benchmark scripts to call before they measure. Why: under the kernel's autogroup
# scheduling any busy process in another session, whatever its priority, takes its
# session's share of the CPU from the node (doc/performance.md, OpenMP waiting), so a
# ratio measured beside one is not this tree's. Never fails: it only reports.
#
#   scripts/busy_processes.sh [PREFIX]     # PREFIX starts each line, e.g. "[bench]"

prefix="${1:-[busy]}"
sample() {  # pid ticks comm, for every process (fields after the comm, which may hold spaces)
  for stat in /proc/[0-9]*/stat; do
    read -r line < "$stat" 2> /dev/null || continue
    local pid="${line%% *}" comm="${line#*(}" rest="${line##*) }"
    comm="${comm%)*}"
    # shellcheck disable=SC2086  # split the fields on purpose
    set -- $rest
    echo "$pid $((${12} + ${13})) ${comm// /_}"
  done
}
before="$(sample)"
sleep 1
after="$(sample)"
hz="$(getconf CLK_TCK 2> /dev/null || echo 100)"
busy="$(awk -v self=$$ -v hz="$hz" 'NR == FNR { t[$1] = $2; next }
  ($1 in t) && $1 != self { pct = 100 * ($2 - t[$1]) / hz; if (pct > 10) printf "%s %s %d%%\n", $1, $3, pct }' \
  <(echo "$before") <(echo "$after"))"
if [ -z "$busy" ]; then
  echo "$prefix quiet host: no process used more than 10 % of a CPU over 1 s"
else
  echo "$prefix WARNING: busy processes (pid, name, % of a CPU over 1 s); a ratio measured beside them moves:"
  while read -r line; do echo "$prefix   $line"; done <<< "$busy"
fi
exit 0
