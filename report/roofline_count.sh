#!/bin/sh
# Instructions per element of every roofline kernel, counted with callgrind
# (independent of the machine's load): each kernel's in-cache batch runs
# 1 and 3 times inside roofline::counted_region; the difference over two
# runs' elements is the count per element (warm-up and setup excluded).
# Usage: sh report/roofline_count.sh   (from the workspace root)
set -e
cargo build --release -p coif-report --example roofline_count >/dev/null 2>&1
bin=target/release/examples/roofline_count
count() { # kernel reps -> Ir inside counted_region
    out=$(mktemp)
    valgrind --tool=callgrind --callgrind-out-file="$out" --collect-atstart=no \
        --toggle-collect='*counted_region*' "$bin" "$1" "$2" >/dev/null 2>&1
    callgrind_annotate "$out" 2>/dev/null | awk '/PROGRAM TOTALS/ {gsub(",", "", $1); print $1}'
    rm -f "$out"
}
m1=$(count mixed 100000); m3=$(count mixed 300000)
echo "mixed loop: $(echo "($m3 - $m1) / 200000" | bc -l) instructions per iteration"
$bin list | while read -r k; do
    n=$($bin "$k" 1)
    a=$(count "$k" 1); b=$(count "$k" 3)
    echo "$k: $(echo "($b - $a) / (2 * $n)" | bc -l) instructions per element"
done
