#!/bin/sh
# What bounds the step with every term (issue 36): the hinge's own
# arithmetic or its fourth vertex's gather and scatter? Builds sb_bench
# twice, as it is and with bench/hinge_bound.patch applied to a copy of
# the tree (the carried hinge's fourth vertex neither gathered nor
# scattered: it is the wing's apex mirrored through the edge, and its
# force is added to a vertex the triangle holds in registers; the
# arithmetic is unchanged, the forces are wrong), then times, interleaved,
# the default terms, all terms, and all terms without that gather and
# scatter: the rate any layout that carries the hinge without a gather or
# scatter of its own (triangle pairs) could at best reach.
#
#   bench/hinge_bound.sh [--cases sheet_100k,sheet_1m] [--rounds N] [--threads-list 1,2]
#
# Writes bench/results/hinge_bound.csv (round, case, configuration,
# threads, steps/s) and prints it. Needs git (git apply) and cmake.
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
CASES=sheet_100k,sheet_1m
ROUNDS=3
THREADS=1,2
while [ $# -gt 0 ]; do
    case $1 in
        --cases) CASES=$2; shift 2 ;;
        --rounds) ROUNDS=$2; shift 2 ;;
        --threads-list) THREADS=$2; shift 2 ;;
        -h|--help) sed -n '2,16p' "$0"; exit 0 ;;
        *) echo "bench/hinge_bound.sh: unknown option $1" >&2; exit 2 ;;
    esac
done
BUILD=$ROOT/build
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target sb_bench >/dev/null

COPY=$(mktemp -d)
trap 'rm -rf "$COPY"' EXIT
(cd "$ROOT" && tar cf - --exclude='./build*' --exclude=./.git .) | (cd "$COPY" && tar xf -)
(cd "$COPY" && git apply "$ROOT/bench/hinge_bound.patch")
cmake -S "$COPY" -B "$COPY/build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$COPY/build" -j "$(nproc)" --target sb_bench >/dev/null

CSV=$ROOT/bench/results/hinge_bound.csv
echo "round,case,configuration,threads,steps_per_s" >"$CSV"
# time ROUND CONFIGURATION BINARY [--all-terms]: one sb_bench run, its rows into the CSV
time_case() {
    round=$1 configuration=$2 binary=$3
    shift 3
    "$binary" --cases "$CASES" --threads-list "$THREADS" --no-reference "$@" --csv /dev/null |
        awk -v r="$round" -v c="$configuration" '$4 == "fast" && $8 ~ /^[0-9.]+$/ { print r "," $1 "," c "," $5 "," $8 }' >>"$CSV"
}
for round in $(seq "$ROUNDS"); do
    time_case "$round" default "$BUILD/bench/sb_bench"
    time_case "$round" all_terms "$BUILD/bench/sb_bench" --all-terms
    time_case "$round" all_terms_no_hinge_gather "$COPY/build/bench/sb_bench" --all-terms
done
echo "load average $(cut -d' ' -f1-3 /proc/loadavg) at the end" >&2
cat "$CSV"
