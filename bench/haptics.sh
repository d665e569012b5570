#!/bin/sh
# The haptics benchmark: builds Release and runs sb_bench_haptics (the 1 kHz
# servo thread beside the simulation of ~3 200, 10 000 and 100 000-vertex
# sheets: its period and lateness, the contact model's age, and the
# simulation's steps per second with and without it).
#
#   bench/haptics.sh [--build DIR] [--seconds S] [--threads N]
#
# S seconds per measurement (the issue asks 60: six measurements, six
# minutes). Writes bench/results/haptics.csv and, with the load averages
# before and after, bench/results/haptics.md (the hand-written notes below
# its table are kept). Run it on an otherwise idle machine if you can.
set -eu

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$ROOT/build
ARGS=
while [ $# -gt 0 ]; do
    case $1 in
        --build) BUILD=$2; shift 2 ;;
        -h|--help) sed -n '2,12p' "$0"; exit 0 ;;
        *) ARGS="$ARGS $1"; shift ;;
    esac
done
RESULTS=$ROOT/bench/results
mkdir -p "$RESULTS"

echo "== build (Release) in $BUILD"
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j 2 --target sb_bench_haptics >/dev/null

before=$(cut -d' ' -f1-3 /proc/loadavg)
# shellcheck disable=SC2086
"$BUILD/bench/sb_bench_haptics" $ARGS | tee "$RESULTS/haptics.csv"
after=$(cut -d' ' -f1-3 /proc/loadavg)

notes=
[ -f "$RESULTS/haptics.md" ] && notes=$(sed -n '/^## Notes/,$p' "$RESULTS/haptics.md")
{
    echo "# Haptics: the servo thread beside the simulation"
    echo
    echo "$(date -u +%Y-%m-%d) on $(nproc) cores; load averages before $before, after $after."
    echo
    echo "| vertices | steps/s alone | with servo | ratio | period median / p99 / max (ms) | worst lateness (ms) | model age median / p99 (ms) | SCHED_FIFO |"
    echo "|---|---|---|---|---|---|---|---|"
    tail -n +2 "$RESULTS/haptics.csv" | awk -F, '{printf "| %s | %s | %s | %s | %s / %s / %s | %s | %s / %s | %s |\n", $1, $4, $5, $6, $8, $9, $10, $11, $12, $13, $14}'
    echo
    [ -n "$notes" ] && echo "$notes"
} > "$RESULTS/haptics.md"
echo "== wrote $RESULTS/haptics.csv and haptics.md"
