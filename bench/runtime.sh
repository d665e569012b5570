#!/bin/sh
# The runtime benchmark: builds Release and runs sb_bench_runtime, which
# measures the solver's wait policies (spin, yield, passive; pinned or not)
# on the 100k sheet alone and beside a competing 1 kHz thread, and the cost
# of sb_solver_publish against a step (10k and 100k sheets).
#
#   bench/runtime.sh [--build DIR] [--quick] [sb_bench_runtime options]
#
# Writes bench/results/runtime.csv and runtime.md (the md's hand-written
# "## Conclusions" section is kept; re-read it against the new numbers).
# Takes 2.5 to 4 minutes: a measurement during which other processes kept
# the cores busy is repeated, within a time budget (sb_bench_runtime --help).
# Run it on an otherwise idle machine if you can; the load averages at the
# top of runtime.md and the "others" columns tell how idle it was.
set -eu

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$ROOT/build
ARGS=
while [ $# -gt 0 ]; do
    case $1 in
        --build) BUILD=$2; shift 2 ;;
        -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
        *) ARGS="$ARGS $1"; shift ;;
    esac
done
RESULTS=$ROOT/bench/results
mkdir -p "$RESULTS"

echo "== build (Release) in $BUILD"
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target sb_bench_runtime

echo "== sb_bench_runtime$ARGS"
# shellcheck disable=SC2086
"$BUILD/bench/sb_bench_runtime" --csv "$RESULTS/runtime.csv" --md "$RESULTS/runtime.md" $ARGS
echo "bench/runtime.sh: results in $RESULTS/runtime.csv and runtime.md"
