#!/bin/sh
# One command for the committed benchmark results: builds Release, runs
# sb_bench on every case, the LAMMPS peer on the same meshes, and the chart.
#
#   bench/run.sh [--cases small|all|NAME,NAME] [--quick] [--build DIR] [--no-lammps]
#
# Writes bench/results/throughput.csv, machine.txt, lammps.csv and
# throughput.png. Installs gnuplot-nox (and, through bench/lammps/run.sh,
# lammps and openmpi-bin) when missing, as root. Run it on an otherwise idle
# machine: the timings share the cores with everything else.
set -eu

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$ROOT/build
CASES=all
QUICK=
LAMMPS=yes
while [ $# -gt 0 ]; do
    case $1 in
        --cases) CASES=$2; shift 2 ;;
        --quick) QUICK=--quick; shift ;;
        --build) BUILD=$2; shift 2 ;;
        --no-lammps) LAMMPS=; shift ;;
        -h|--help) sed -n '2,11p' "$0"; exit 0 ;;
        *) echo "bench/run.sh: unknown option $1" >&2; exit 2 ;;
    esac
done
RESULTS=$ROOT/bench/results

if ! command -v gnuplot >/dev/null 2>&1; then
    if [ "$(id -u)" -ne 0 ]; then
        echo "bench/run.sh: gnuplot is missing; run as root to install gnuplot-nox" >&2
        exit 1
    fi
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq gnuplot-nox >/dev/null
fi

echo "== build (Release) in $BUILD"
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target sb_bench sb_lammps_export

echo "== sb_bench --cases $CASES"
"$BUILD/bench/sb_bench" --cases "$CASES" $QUICK --csv "$RESULTS/throughput.csv"

if [ -n "$LAMMPS" ]; then
    echo "== LAMMPS peer"
    sh "$ROOT/bench/lammps/run.sh" --cases "$CASES" --build "$BUILD"
fi

echo "== chart"
gnuplot -e "results='$RESULTS'" "$ROOT/bench/plot.gp"
echo "bench/run.sh: results in $RESULTS"
