#!/bin/sh
# softbond sweep's throughput: 64 short cases (the pinned sheet of
# tests/data/sweep/stability.yaml at 24 x 24 vertices, 2000 steps each) run by 1, 2 and 4
# worker processes (--workers) and by mpirun with 1, 2 and 4 working ranks
# (-np 2, 3, 5: rank 0 hands out the cases); and the cost a case carries
# whatever it simulates, from 64 cases of a single step. Writes
# bench/results/sweep.csv; bench/results/sweep.md says what it means.
#
#   bench/sweep.sh [BUILD]      (BUILD: a configured build folder, default build)
set -eu
. "$(dirname "$0")/common.sh"
BUILD=${1:-$ROOT/build}
bench_build "$BUILD" softbond_cli
PROGRAM=$BUILD/softbond
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
export OMPI_MCA_btl=self,vader OMPI_MCA_btl_vader_single_copy_mechanism=none OMPI_MCA_rmaps_base_oversubscribe=1

# 64 cases: bond.k over 8 values by gravity over 8, every case stable
sweep_file() { # NAME SETS
    cat >"$WORK/$1.yaml" <<YAML
scene: $ROOT/tests/data/sweep/stability.yaml
set: [$2]
vary:
  - {key: bond.k, range: {from: 10, to: 100, count: 8, scale: log}}
  - {key: gravity, format: "[0, 0, %g]", range: {from: -1, to: -10, count: 8}}
metrics: [{name: kinetic_max, column: kinetic, of: max}]
YAML
}
sweep_file short "mesh.nx=24, mesh.ny=24, dt=0.0001, duration=0.2, frame_interval=0.02"
sweep_file empty "dt=0.0001, duration=0.0001, frame_interval=0.0001"

echo "case_set,farm,workers,ranks,wall_s,cpu_s,cases_per_s,cpu_ms_per_case" >"$WORK/sweep.csv"
measure() { # CASES FARM WORKERS RANKS COMMAND...
    cases=$1 farm=$2 workers=$3 ranks=$4
    shift 4
    rm -rf "$WORK/out"
    /usr/bin/time -f "%e %U %S" -o "$WORK/time" "$@" >/dev/null
    read -r wall user system <"$WORK/time"
    grep -c '^[0-9]' "$WORK/out/sweep.csv" | grep -qx 64 || { echo "bench/sweep.sh: $farm $workers: not 64 rows" >&2; exit 1; }
    # the CPU time of every process the command waited for: the runs, the ranks, mpirun
    awk -v c="$cases" -v f="$farm" -v w="$workers" -v r="$ranks" -v e="$wall" -v cpu="$user + $system" \
        'BEGIN { split(cpu, p, " [+] "); t = p[1] + p[2];
                 printf "%s,%s,%d,%d,%.2f,%.2f,%.2f,%.1f\n", c, f, w, r, e, t, 64 / e, 1000 * t / 64 }' |
        tee -a "$WORK/sweep.csv"
}
for cases in short empty; do
    for workers in 1 2 4; do
        measure $cases local $workers 1 "$PROGRAM" sweep "$WORK/$cases.yaml" --output "$WORK/out" --workers $workers --threads 1
        measure $cases mpi $workers $((workers + 1)) mpirun --allow-run-as-root --oversubscribe -np $((workers + 1)) \
            "$PROGRAM" sweep "$WORK/$cases.yaml" --output "$WORK/out" --threads 1
    done
done
# rank 0's own CPU time per case, the farm's serial part: each rank timed alone
rm -rf "$WORK/out"
mpirun --allow-run-as-root --oversubscribe -np 5 sh -c \
    '/usr/bin/time -f "%U %S" -o "$0/rank.$OMPI_COMM_WORLD_RANK" "$1" sweep "$2" --output "$0/out" --threads 1' \
    "$WORK" "$PROGRAM" "$WORK/empty.yaml" >/dev/null
awk '{ printf "rank0,mpi,4,5,,%.3f,,%.2f\n", $1 + $2, 1000 * ($1 + $2) / 64 }' "$WORK/rank.0" | tee -a "$WORK/sweep.csv"
cp "$WORK/sweep.csv" "$RESULTS/sweep.csv"
echo "bench/sweep.sh: $RESULTS/sweep.csv"
