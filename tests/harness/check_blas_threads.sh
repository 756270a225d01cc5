#!/bin/sh
# SPDX-License-Identifier: MIT
# CHOLMOD's results do not depend on how many threads BLAS is offered: the liver pressed under
# corotational_fem with the exact (CHOLMOD) solver into contact, once with OpenBLAS and OpenMP told to use one
# thread and once two, writes bit-identical frames (softbench pins OpenBLAS to one thread).
# Usage: check_blas_threads.sh SOFTBENCH (from the repository root).
softbench="$1"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
sed -e 's/"duration": 5.0/"duration": 2.4/' \
    -e 's|"mesh": "data/|"mesh": "'"$PWD"'/scenes/data/|g' \
    -e 's/"corotational_fem": { "rayleigh_mass": 5.0 }/"corotational_fem": { "rayleigh_mass": 5.0, "solver": "cholmod" }/' \
    scenes/liver_press.json > "$work/press.json"
grep -q '"solver": "cholmod"' "$work/press.json" || { echo "the scene edit did not take"; exit 1; }
for threads in 1 2; do
  OPENBLAS_NUM_THREADS=$threads OMP_NUM_THREADS=$threads "$softbench" run "$work/press.json" \
    --model corotational_fem --frames-every 20 --out "$work/t$threads" > /dev/null 2> "$work/err" \
    || { cat "$work/err"; exit 1; }
done
count=$(find "$work/t1/frames" -name '*.vtu' | wc -l)
[ "$count" -ge 3 ] || { echo "expected frames, found $count"; exit 1; }
diff -r "$work/t1/frames" "$work/t2/frames" > /dev/null \
  || { echo "frames differ between one and two threads"; exit 1; }
echo "$count frames bit-identical at one and two threads"
