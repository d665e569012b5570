#!/bin/sh
# The integrator study in one command: builds a double-precision Release in
# build-study/ (so the converged reference is not limited by float), runs
# sb_study (stability, work-precision at the middle and at a corner, the
# paper's tables in paper_tables.md, model accuracy, level of detail), and draws the charts
# in bench/results with bench/study.gp.
#
#   bench/study.sh [--quick]
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$ROOT/build-study
command -v gnuplot >/dev/null 2>&1 || {
    [ "$(id -u)" -eq 0 ] || { echo "bench/study.sh: run as root to install gnuplot-nox" >&2; exit 1; }
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq gnuplot-nox >/dev/null
}
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release -DSB_DOUBLE=ON -DSB_BUILD_TESTS=OFF >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target sb_study
"$BUILD/bench/sb_study" "$@" --out "$ROOT/bench/results"
cd "$ROOT" && gnuplot bench/study.gp
echo "bench/study.sh: results in $ROOT/bench/results"
