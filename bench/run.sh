#!/bin/sh
# One command for the committed benchmark results: builds Release, runs
# sb_bench on every case, the LAMMPS peer on the same meshes, and the chart.
#
#   bench/run.sh [--cases small|all|NAME,NAME] [--quick] [--build DIR] [--no-lammps] [--all-terms]
#
# Writes bench/results/throughput.csv, machine.txt, lammps.csv and
# throughput.png; with --all-terms (sb_bench --all-terms: the damped spring
# and the hinge too, LAMMPS with the terms it has, sheets only)
# throughput_all_terms.csv, lammps_all_terms.csv, throughput_all_terms.png
# and machine.txt. Installs gnuplot-nox (and, through bench/lammps/run.sh,
# lammps and openmpi-bin) when missing, as root. Run it on an otherwise idle
# machine: the timings share the cores with everything else.
set -eu

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$ROOT/build
CASES=all
QUICK=
LAMMPS=yes
ALL_TERMS=
while [ $# -gt 0 ]; do
    case $1 in
        --cases) CASES=$2; shift 2 ;;
        --quick) QUICK=--quick; shift ;;
        --build) BUILD=$2; shift 2 ;;
        --no-lammps) LAMMPS=; shift ;;
        --all-terms) ALL_TERMS=--all-terms; shift ;;
        -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
        *) echo "bench/run.sh: unknown option $1" >&2; exit 2 ;;
    esac
done
RESULTS=$ROOT/bench/results
SUFFIX=${ALL_TERMS:+_all_terms}

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

echo "== sb_bench --cases $CASES $ALL_TERMS"
"$BUILD/bench/sb_bench" --cases "$CASES" $QUICK $ALL_TERMS --csv "$RESULTS/throughput$SUFFIX.csv"

if [ -n "$LAMMPS" ]; then
    echo "== LAMMPS peer"
    sh "$ROOT/bench/lammps/run.sh" --cases "$CASES" --build "$BUILD" $ALL_TERMS
fi

echo "== chart"
gnuplot -e "results='$RESULTS'; terms='${ALL_TERMS:+all}'" "$ROOT/bench/plot.gp"
echo "bench/run.sh: results in $RESULTS"
