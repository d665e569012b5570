#!/bin/sh
# The tearing benchmark: builds Release and runs sb_bench_tearing, which
# pulls the 100k sheet apart with and without break limits, interleaved,
# and times every step (bench/bench_tearing.c says what it reports).
# Writes bench/results/tearing.csv and tearing.md. About a minute.
#
#   bench/tearing.sh [sb_bench_tearing options]
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$ROOT/build
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target sb_bench_tearing
cd "$ROOT"
"$BUILD/bench/sb_bench_tearing" --csv bench/results/tearing.csv --md bench/results/tearing.md "$@"
