#!/bin/sh
# SPDX-License-Identifier: MIT
# Ctrl-C as a user presses it: a run of the slow reference is stopped between two steps, ends
# with status 130 and one line, and leaves no metrics of the unfinished run and no temporary.
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
if [ -n "$(find "$out" -type f)" ]; then
  echo "files were left behind:"; find "$out" -type f; exit 1
fi
rm -f "$out.err"
echo "stopped with 130, nothing written"
