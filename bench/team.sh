#!/bin/sh
# The team beside a busy core (issue 36): xpbd (5 sweeps) and vbd (4
# sweeps) on the default scene's sheet at 100 x 100 vertices, dt = 1 ms,
# and Verlet (the fused step) on it at 316 x 316 (99 856 vertices, every
# term of the scene), dt = 2 us (its angle term is stiff at 3 mm spacing),
# the default passive waits, on 1 and 2 threads, first on the machine as it
# is ("quiet"), then with one core loaded by a niced busy loop
# (nice -n 19 sh -c 'while :; do :; done'), the loop stopped after.
#
#   [SOFTBOND=program] bench/team.sh [--steps N] [--repeats R] [--csv FILE]
#
# A configuration's ms per step is the difference of two runs (2 and 2 + N
# steps, default N = 400: vbd at 4 sweeps runs this sheet away after about
# 0.6 s; start-up and loading cancel), the least and the median of R
# repeats (default 3), the configurations interleaved so that a busy moment
# of a shared machine hits all alike. Writes FILE (default
# bench/results/team.csv) and prints it, with the load averages before and
# after (how idle the machine was besides the loop).
set -eu

. "$(dirname "$0")/common.sh"
STEPS=400
REPEATS=3
CSV=$ROOT/bench/results/team.csv
while [ $# -gt 0 ]; do
    case $1 in
        --steps) STEPS=$2; shift 2 ;;
        --repeats) REPEATS=$2; shift 2 ;;
        --csv) CSV=$2; shift 2 ;;
        -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
        *) echo "bench/team.sh: unknown option $1 (--steps N, --repeats R, --csv FILE)" >&2; exit 2 ;;
    esac
done
bench_program
SCENE=$ROOT/scenes/default.yaml
TMP=$(mktemp -d)
LOOP=
stop_loop() { [ -z "$LOOP" ] || kill "$LOOP" 2>/dev/null || true; LOOP=; }
trap 'stop_loop; rm -rf "$TMP"' EXIT INT TERM

# The case's --set options.
case_options() {
    case $1 in
        xpbd) echo "--set integrator=xpbd --set pbd.iterations=5 --set mesh.nx=100 --set mesh.ny=100" ;;
        vbd) echo "--set integrator=vbd --set vbd.iterations=4 --set mesh.nx=100 --set mesh.ny=100" ;;
        verlet) echo "--set integrator=verlet --set mesh.nx=316 --set mesh.ny=316" ;;
    esac
}

# The case's step, s.
case_dt() {
    case $1 in
        verlet) echo 2e-6 ;;
        *) echo 0.001 ;;
    esac
}

# Wall seconds of one run of case $1, $2 steps (the rest: options).
run_seconds() {
    case=$1
    dt=$(case_dt "$case")
    n=$2
    shift 2
    t=$(awk -v n="$n" -v dt="$dt" 'BEGIN { printf "%.6g", n * dt }')
    # shellcheck disable=SC2046
    /usr/bin/time -f "%e" -o "$TMP/time" "$SB" run "$SCENE" --set output.frames=false --output "$TMP/out" \
        $(case_options "$case") --set dt="$dt" --set duration="$t" --set frame_interval="$t" \
        --set wait=passive "$@" >/dev/null 2>"$TMP/err" || {
        echo "bench/team.sh: softbond run $*: $(tail -1 "$TMP/err")" >&2
        exit 1
    }
    cat "$TMP/time"
}

# ms per step of case $1 on $2 threads: one measurement.
ms_per_step() {
    short=$(run_seconds "$1" 2 --threads "$2")
    long=$(run_seconds "$1" $((2 + STEPS)) --threads "$2")
    awk -v a="$short" -v b="$long" -v n="$STEPS" 'BEGIN { printf "%.3f\n", 1000 * (b - a) / n }'
}

# Every case and thread count under load $1 (quiet, loaded), R times interleaved.
measure() {
    for r in $(seq "$REPEATS"); do
        for c in xpbd vbd verlet; do
            for threads in 1 2; do
                ms=$(ms_per_step "$c" "$threads") # a failed run stops the script (set -e)
                echo "$1 $c $threads $ms" >>"$TMP/rows"
            done
        done
    done
}

: >"$TMP/rows"
echo "program: $SB"
echo "load averages before: $(cut -d' ' -f1-3 /proc/loadavg)"
measure quiet
nice -n 19 sh -c 'while :; do :; done' &
LOOP=$!
sleep 1
measure loaded
stop_loop
echo "load averages after: $(cut -d' ' -f1-3 /proc/loadavg)"

{
    echo "load,case,threads,ms_per_step_least,ms_per_step_median,repeats"
    for load in quiet loaded; do
        for c in xpbd vbd verlet; do
            for threads in 1 2; do
                awk -v l="$load" -v c="$c" -v t="$threads" '$1 == l && $2 == c && $3 == t { print $4 }' "$TMP/rows" |
                    sort -n | awk -v l="$load" -v c="$c" -v t="$threads" '{ v[NR] = $1 }
                        END { printf "%s,%s,%s,%.3f,%.3f,%d\n", l, c, t, v[1], v[int((NR + 1) / 2)], NR }'
            done
        done
    done
} >"$CSV"
cat "$CSV"
echo "bench/team.sh: results in $CSV"
