#!/bin/sh
# Issue 16's targets for the implicit integrators, measured with the program
# on the default scene's material (scenes/default.yaml):
#   1. implicit_euler on the default scene (900 vertices) at dt = 10 ms,
#      with implicit.solver cholesky and cg, on 1 and 2 threads;
#   2. vbd at dt = 1 ms (the haptic rate) on sheets of 3 249 and 10 000
#      vertices, beside the Verlet sub-step that the same sheet needs.
# A step's time is the difference of two runs (2 and 2 + N steps) divided
# by N, so the set-up (mesh, colouring, the factorization's analysis) is
# not counted. Writes bench/results/implicit.md.
#
#   bench/implicit.sh [--quick]
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$ROOT/build
OUT=$ROOT/bench/results/implicit.md
QUICK=0
[ "${1:-}" = "--quick" ] && QUICK=1
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target softbond_cli >/dev/null
SB=$BUILD/softbond
SCENE=$ROOT/scenes/default.yaml
TMP=$(mktemp -d)
trap 'rm -rf "$TMP"' EXIT

# wall seconds and CPU seconds of one run: "wall cpu"
run_time() {
    /usr/bin/time -f "%e %U %S" -o "$TMP/time" "$SB" run "$SCENE" --set output.frames=false \
        --output "$TMP/out" "$@" >/dev/null 2>"$TMP/err" || {
        echo "bench/implicit.sh: softbond run $*: $(tail -1 "$TMP/err")" >&2
        return 1
    }
    awk '{printf "%s %.3f\n", $1, $2 + $3}' "$TMP/time"
}

# ms per step (wall and CPU) over N steps of dt: "wall_ms cpu_ms"
per_step() {
    dt=$1 n=$2
    shift 2
    short=$(awk -v dt="$dt" 'BEGIN { printf "%.6g", 2 * dt }')
    long=$(awk -v dt="$dt" -v n="$n" 'BEGIN { printf "%.6g", (2 + n) * dt }')
    a=$(run_time --set dt="$dt" --set duration="$short" --set frame_interval="$short" "$@")
    b=$(run_time --set dt="$dt" --set duration="$long" --set frame_interval="$long" "$@")
    echo "$a $b" | awk -v n="$n" '{ printf "%.2f %.2f\n", 1000 * ($3 - $1) / n, 1000 * ($4 - $2) / n }'
}

# The last log row's Newton, CG and unconverged columns.
solver_work() { tail -1 "$TMP/out/log.csv" | awk -F, '{ print $13, $14, $15 }'; }

# The fewest of 1, 2, 5, 10, 20, 40, 80 sub-steps per 1 ms at which Verlet
# runs 0.1 s without running away.
verlet_substeps() {
    for k in 1 2 5 10 20 40 80; do
        dt=$(awk -v k="$k" 'BEGIN { printf "%.6g", 0.001 / k }')
        if "$SB" run "$SCENE" --set output.frames=false --output "$TMP/out" --set duration=0.1 \
            --set frame_interval=0.1 --set dt="$dt" "$@" >/dev/null 2>&1; then
            echo "$k"
            return
        fi
    done
    echo ">80"
}

STEPS=20
VBD_STEPS=20
[ $QUICK -eq 1 ] && STEPS=4 && VBD_STEPS=4
{
    echo "# Implicit integrators (issue 16): measured by bench/implicit.sh"
    echo
    echo "$(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git -C "$ROOT" rev-parse --short HEAD)," \
        "$(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the start."
    echo "A step's time: two runs of 2 and 2 + N steps, the difference over N (set-up not counted);"
    echo "wall clock and CPU (user + system, all threads)."
    echo
    echo "## implicit_euler, default scene (30 x 30 = 900 vertices), dt = 10 ms, $STEPS steps"
    echo
    echo "| solver | threads | wall ms/step | CPU ms/step | Newton | CG | unconverged |"
    echo "|---|--:|--:|--:|--:|--:|--:|"
    for solver in cholesky cg; do
        for threads in 1 2; do
            t=$(per_step 0.01 $STEPS --set integrator=implicit_euler --set implicit.solver=$solver --threads $threads)
            w=$(solver_work)
            echo "| $solver | $threads | ${t% *} | ${t#* } | $(echo "$w" | awk '{print $1}') |" \
                "$(echo "$w" | awk '{print $2}') | $(echo "$w" | awk '{print $3}') |"
        done
    done
    echo
    echo "Newton, CG and unconverged: the whole run of 2 + $STEPS steps. Target: <= 10 ms a step."
    echo
    echo "## vbd at dt = 1 ms, the default scene's material, 2 threads, $VBD_STEPS steps"
    echo
    echo "| sheet | vertices | Verlet sub-steps per 1 ms | vbd sweeps | wall ms/step | CPU ms/step | finite after the run |"
    echo "|---|--:|--:|--:|--:|--:|---|"
    for n in 57 100; do
        sub=$(verlet_substeps --set mesh.nx=$n --set mesh.ny=$n)
        for sweeps in 10 4; do
            t=$(per_step 0.001 $VBD_STEPS --set integrator=vbd --set vbd.iterations=$sweeps \
                --set mesh.nx=$n --set mesh.ny=$n --threads 2)
            finite=$(tail -1 "$TMP/out/log.csv" | awk -F, '{ print ($9 == $9 + 0) ? "yes" : "no" }')
            echo "| $n x $n | $((n * n)) | $sub | $sweeps | ${t% *} | ${t#* } | $finite |"
        done
    done
    "$SB" run "$SCENE" --set output.frames=false --output "$TMP/out" --set mesh.nx=57 --set mesh.ny=57 \
        --set integrator=vbd --set vbd.iterations=4 --set dt=0.001 --set duration=0.1 --set frame_interval=0.01 \
        --threads 2 >/dev/null 2>&1 && long="ran 0.1 s (100 steps)" || long="failed within 0.1 s"
    echo
    echo "Verlet sub-steps: the fewest of 1, 2, 5, 10, 20, 40, 80 per 1 ms that ran 0.1 s without a"
    echo "vertex running away. Finite: the energies after the 2 + $VBD_STEPS steps timed; vbd with 4"
    echo "sweeps on the 57 x 57 sheet $long. Target: vbd stable at 1 ms where Verlet needs >= 10,"
    echo "below 1 ms a step."
} >"$OUT"
cat "$OUT"
