# Sourced by a benchmark script (bench/viewer.sh): ROOT (the repository),
# RESULTS (bench/results, made), bench_build BUILD TARGET (configures
# Release in BUILD and builds TARGET quietly) and bench_program (sets SB).
ROOT=$(cd "$(dirname "$0")/.." && pwd)
RESULTS=$ROOT/bench/results
mkdir -p "$RESULTS"

bench_build() {
    echo "== build (Release) in $1"
    cmake -S "$ROOT" -B "$1" -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build "$1" -j 2 --target "$2" >/dev/null
}

# SB: the program to time: $SOFTBOND when set (an A/B of two builds, run
# alternately in the same minutes), else this tree's, built in build/.
bench_program() {
    if [ -n "${SOFTBOND:-}" ]; then
        SB=$SOFTBOND
    else
        bench_build "$ROOT/build" softbond_cli >&2
        SB=$ROOT/build/softbond
    fi
}
