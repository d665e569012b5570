#!/bin/sh
# Mesh import benchmark in one command: builds Release in build/ and runs
# sb_bench_mesh (load + factory + compile of a 1M-triangle OBJ, vicinity
# springs for 1M points), writing bench/results/mesh_load.csv. As root the
# page cache is dropped before the first trial (a cold read from disk).
#
#   bench/mesh.sh [--trials N] [--build DIR]
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$ROOT/build
TRIALS=5
while [ $# -gt 0 ]; do
    case $1 in
        --trials) TRIALS=$2; shift 2 ;;
        --build) BUILD=$2; shift 2 ;;
        -h|--help) sed -n '2,7p' "$0"; exit 0 ;;
        *) echo "bench/mesh.sh: unknown option $1" >&2; exit 2 ;;
    esac
done
COLD=
[ "$(id -u)" -eq 0 ] && COLD=--cold
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target sb_bench_mesh
"$BUILD/bench/sb_bench_mesh" --trials "$TRIALS" $COLD --csv "$ROOT/bench/results/mesh_load.csv"
echo "bench/mesh.sh: results in $ROOT/bench/results/mesh_load.csv"
