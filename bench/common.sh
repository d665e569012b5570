# Sourced by a benchmark script (bench/viewer.sh): ROOT (the repository),
# RESULTS (bench/results, made) and bench_build BUILD TARGET (configures
# Release in BUILD and builds TARGET quietly).
ROOT=$(cd "$(dirname "$0")/.." && pwd)
RESULTS=$ROOT/bench/results
mkdir -p "$RESULTS"

bench_build() {
    echo "== build (Release) in $1"
    cmake -S "$ROOT" -B "$1" -DCMAKE_BUILD_TYPE=Release >/dev/null
    cmake --build "$1" -j 2 --target "$2" >/dev/null
}
