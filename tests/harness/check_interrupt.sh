#!/bin/sh
# SPDX-License-Identifier: MIT
# Ctrl-C as a user presses it: a run of the slow reference is stopped between two steps, ends
# with status 130 and one line, and writes what it measured, marked interrupted, with no
# temporary left. A run killed outright (SIGKILL) leaves its staging folder and the last
# folder as it was, and the next run clears the staging folder.
# Usage: check_interrupt.sh SOFTBENCH (from the repository root).
softbench="$1"
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
"$softbench" run scenes/liver_press.json --model neo_hookean --out "$out" 2> "$out.err" &
pid=$!
sleep 3
kill -INT "$pid"
wait "$pid"
code=$?
cat "$out.err"
if [ "$code" -ne 130 ]; then
  echo "expected status 130, got $code"
  exit 1
fi
grep -q "softbench: interrupted" "$out.err" || { echo "no 'interrupted' line"; exit 1; }
grep -q '"interrupted": true' "$out/metrics.json" || { echo "metrics.json not marked interrupted"; exit 1; }
grep -q "interrupted after step" "$out/summary.md" || { echo "summary.md not marked interrupted"; exit 1; }
if [ -n "$(find "$out" -name '*.tmp*')" ]; then
  echo "temporaries were left behind:"; find "$out" -name '*.tmp*'; exit 1
fi
staging_left() {
  ls -a "$(dirname "$out")" | grep -q "^\.$(basename "$out")\.staging-"
}
if staging_left; then
  echo "a staging folder was left behind"; exit 1
fi

"$softbench" run scenes/liver_press.json --model neo_hookean --out "$out" 2> "$out.err" &
pid=$!
sleep 3
kill -KILL "$pid"
wait "$pid"
staging_left || { echo "SIGKILL left no staging folder (was the run staged?)"; exit 1; }
grep -q '"interrupted": true' "$out/metrics.json" || { echo "SIGKILL touched the last folder"; exit 1; }
"$softbench" run scenes/liver_gravity.json --model shape_matching --out "$out" > /dev/null 2> "$out.err" \
  || { cat "$out.err"; echo "the run after SIGKILL failed"; exit 1; }
if staging_left; then
  echo "the run after SIGKILL did not clear the killed run's staging folder"; exit 1
fi
[ -f "$out/metrics.json" ] && [ -f "$out/summary.md" ] || { echo "no metrics after SIGKILL"; exit 1; }
rm -f "$out.err"
echo "stopped with 130, measures written marked interrupted; a killed run's staging cleared by the next"
