#!/bin/sh
# Issue 16's targets for the implicit integrators, measured with the program
# on the default scene's material (scenes/default.yaml):
#   1. implicit_euler on the default scene (900 vertices) at dt = 10 ms,
#      with implicit.solver cholesky and cg, on 1 and 2 threads;
#   2. vbd at dt = 1 ms (the haptic rate) on sheets of 3 249 and 10 000
#      vertices, beside the Verlet sub-step that the same sheet needs, with
#      the reference sweeps (double, scalar) and the fast ones (kernels/integrators/fast_vbd.c),
#      with the default material and with it softened to where Verlet needs
#      10 sub-steps per 1 ms (issue 16's threshold);
#   3. vbd (fast) on the 100k sheet at 10 x Verlet's largest stable step,
#      against a Verlet step, and both runs' error against a fine Verlet run.
# A step's time is the difference of two runs (2 and 2 + N steps) divided
# by N, so the set-up (mesh, colouring, the factorization's analysis) is
# not counted; each run's time is the least of REPEATS runs (wall and CPU
# apart). Writes bench/results/implicit.md.
#
#   [SOFTBOND=program] bench/implicit.sh [--quick] [--implicit-fast] [--vbd] [--default-scene]
# --implicit-fast: only section 4 (implicit_euler on the fast kernels, the
# 100k sheet), printed, bench/results/implicit.md left as it is.
# --vbd: only section 2 (vbd at dt = 1 ms), printed, the file left as it is.
# --default-scene: only section 1 (implicit_euler on the default scene),
# printed, the file left as it is.
# SOFTBOND: time that program instead of building this tree's (an A/B of two
# builds, alternating, in the same minutes).
set -eu
. "$(dirname "$0")/common.sh"
OUT=$ROOT/bench/results/implicit.md
QUICK=0
IMPLICIT_FAST_ONLY=0
VBD_ONLY=0
DEFAULT_ONLY=0
for arg in "$@"; do
    case $arg in
    --quick) QUICK=1 ;;
    --implicit-fast) IMPLICIT_FAST_ONLY=1 ;;
    --vbd) VBD_ONLY=1 ;;
    --default-scene) DEFAULT_ONLY=1 ;;
    *) echo "bench/implicit.sh: unknown option $arg (--quick, --implicit-fast, --vbd, --default-scene)" >&2 && exit 2 ;;
    esac
done
bench_program
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

# The least wall and the least CPU seconds of REPEATS runs: "wall cpu"
REPEATS=1
run_time_least() {
    : >"$TMP/times"
    for _ in $(seq "$REPEATS"); do run_time "$@" >>"$TMP/times" || return 1; done
    awk 'NR == 1 || $1 < w { w = $1 } NR == 1 || $2 < c { c = $2 } END { print w, c }' "$TMP/times"
}

# ms per step (wall and CPU) over N steps of dt: "wall_ms cpu_ms"
per_step() {
    dt=$1 n=$2
    shift 2
    short=$(awk -v dt="$dt" 'BEGIN { printf "%.6g", 2 * dt }')
    long=$(awk -v dt="$dt" -v n="$n" 'BEGIN { printf "%.6g", (2 + n) * dt }')
    a=$(run_time_least --set dt="$dt" --set duration="$short" --set frame_interval="$short" "$@")
    b=$(run_time_least --set dt="$dt" --set duration="$long" --set frame_interval="$long" "$@")
    echo "$a $b" | awk -v n="$n" '{ printf "%.2f %.2f\n", 1000 * ($3 - $1) / n, 1000 * ($4 - $2) / n }'
}

# The last log row's Newton, CG and unconverged columns.
solver_work() { tail -1 "$TMP/out/log.csv" | awk -F, '{ print $13, $14, $15 }'; }

# The fewest sub-steps per 1 ms of the ladder $1 at which Verlet runs 0.1 s
# without running away (the rest: --set options).
verlet_substeps_of() {
    ladder=$1
    shift
    for k in $ladder; do
        dt=$(awk -v k="$k" 'BEGIN { printf "%.6g", 0.001 / k }')
        if "$SB" run "$SCENE" --set output.frames=false --output "$TMP/out" --set duration=0.1 \
            --set frame_interval=0.1 --set dt="$dt" "$@" >/dev/null 2>&1; then
            echo "$k"
            return
        fi
    done
    echo ">80"
}
verlet_substeps() { verlet_substeps_of "1 2 5 10 20 40 80" "$@"; }

# One vbd row on an n x n sheet: kernels, sweeps, timed steps, Chebyshev's
# rho (0: none), the vertex steps' relaxation (1: plain), the material's
# stiffness scale (1: the default's; the rest: --set options of that
# material). With N = 98 the long run of per_step is the 0.1 s stability
# run itself. VBD_WAIT: the team's wait policy (the scene key wait), the
# default's passive unless set: a step of 4 sweeps waits at 32 barriers,
# each a futex sleep and wake-up when passive.
VBD_WAIT=passive
vbd_row() {
    n=$1 kernels=$2 sweeps=$3 steps=$4 rho=${5:-0} relax=${6:-1} row_scale=${7:-1}
    shift $(($# < 7 ? $# : 7))
    set -- "$@" --set integrator=vbd --set vbd.iterations="$sweeps" --set vbd.chebyshev_rho="$rho" \
        --set vbd.relaxation="$relax" --set wait="$VBD_WAIT" \
        --set kernels="$kernels" --set mesh.nx="$n" --set mesh.ny="$n" --threads 2
    if t=$(per_step 0.001 "$steps" "$@" 2>/dev/null); then
        finite=$(tail -1 "$TMP/out/log.csv" | awk -F, '{ print ($9 == $9 + 0) ? "yes" : "no" }')
        [ "$steps" -eq 98 ] && ran="0.1 s" || ran="$((steps + 2)) steps"
        [ "$kernels" = fast ] && long=$(vbd_survival "$@") || long="-"
        echo "| $n x $n | $((n * n)) | $row_scale | $sub | $kernels | $sweeps | $rho | $relax | $VBD_WAIT | ${t% *} | ${t#* } | $ran, finite: $finite | $long |"
    else
        echo "| $n x $n | $((n * n)) | $row_scale | $sub | $kernels | $sweeps | $rho | $relax | $VBD_WAIT | - | - | failed within 0.1 s | - |"
    fi
}

# How long vbd at dt = 1 ms runs (the options: --set ...), at most 2 s:
# "2 s" and the most the total energy rose above its start (too few sweeps
# store stretch energy), or where a vertex ran away.
vbd_survival() {
    if "$SB" run "$SCENE" --set output.frames=false --output "$TMP/out" --set duration=2 --set frame_interval=0.1 \
        --set dt=0.001 "$@" >/dev/null 2>"$TMP/err"; then
        awk -F, 'NR == 2 { start = $9; most = $9 } NR > 2 && $9 > most { most = $9 }
            END { printf "2 s, +%.2g J\n", most - start }' "$TMP/out/log.csv"
    else
        sed -n 's/.*(t = \([0-9.e-]*\) s).*/ran away at \1 s/p' "$TMP/err" | head -1
    fi
}

# The final positions of a run on the 100k sheet (its last frame, OBJ) in
# $TMP/$1, its first in $TMP/start.
final_positions() {
    name=$1
    shift
    rm -rf "$TMP/frames"
    "$SB" run "$SCENE" --output "$TMP/frames" --set output.formats=obj --set mesh.nx=317 --set mesh.ny=317 \
        --set duration="$T100K" --set frame_interval="$T100K" --threads 2 "$@" >/dev/null 2>&1 || return 1
    grep '^v ' "$TMP/frames/frame_000000.obj" | cut -d' ' -f2-4 >"$TMP/start"
    grep '^v ' "$(ls "$TMP"/frames/frame_*.obj | tail -1)" | cut -d' ' -f2-4 >"$TMP/$name"
}

# RMS and largest distance between two position files, and the RMS motion
# from the start: "rms max motion".
position_error() {
    paste -d' ' "$TMP/$1" "$TMP/$2" "$TMP/start" | awk '{
        d = ($1 - $4)^2 + ($2 - $5)^2 + ($3 - $6)^2; s += d; if (d > m) m = d;
        w = ($4 - $7)^2 + ($5 - $8)^2 + ($6 - $9)^2; t += w }
        END { printf "%.3g %.3g %.3g\n", sqrt(s / NR), sqrt(m), sqrt(t / NR) }'
}

# Verlet's largest stable step on the 100k sheet: the largest of a grid
# that runs 0.02 s without a vertex running away (the default material's
# angle term, 0.5 J on 3 mm edges, is what limits it).
VERLET_GRID="2e-5 1e-5 7e-6 5e-6 4e-6 3e-6 2.5e-6 2e-6 1.5e-6 1e-6"
verlet_largest_step() {
    for dt in $VERLET_GRID; do
        if "$SB" run "$SCENE" --set output.frames=false --output "$TMP/out" --set duration=0.02 \
            --set frame_interval=0.02 --set dt="$dt" --set mesh.nx=317 --set mesh.ny=317 --threads 2 >/dev/null 2>&1; then
            echo "$dt"
            return
        fi
    done
    echo "none"
}

# The default scene's stiffnesses times $1 (bond, angle, spring, hinge; its
# stretch-bend is 0), and its spring damping times sqrt($1): the same
# damping ratio. (Unscaled, the damping alone holds Verlet on the 100 x 100
# sheet to 20 sub-steps per 1 ms however soft the sheet: at 1/16 of the
# stiffness it ran 0.1 s at dt = 0.1 ms with 0.0125 N s/m and not with 0.05.)
softened() {
    awk -v s="$1" 'BEGIN { printf "--set bond.k=%.6g --set angle.k=%.6g --set spring.k=%.6g --set bend.k=%.6g --set spring.damping=%.6g\n", 1000 * s, 0.5 * s, 100 * s, 0.0005 * s, 0.05 * sqrt(s) }'
}

# The stiffest scale of the default material (2^(-k/4), k = 0 .. 20) at
# which Verlet runs an n x n sheet 0.1 s with 10 sub-steps per 1 ms.
STIFFNESS_LADDER="1 0.841 0.707 0.595 0.5 0.42 0.354 0.297 0.25 0.21 0.177 0.149 0.125 0.105 0.088 0.0743 0.0625
 0.0526 0.0442 0.0372 0.03125"
threshold_scale() {
    for s in $STIFFNESS_LADDER; do
        # shellcheck disable=SC2046
        if "$SB" run "$SCENE" --set output.frames=false --output "$TMP/out" --set duration=0.1 --set frame_interval=0.1 \
            --set dt=0.0001 --set mesh.nx="$1" --set mesh.ny="$1" $(softened "$s") >/dev/null 2>&1; then
            echo "$s"
            return
        fi
    done
    echo none
}

# Section 2: vbd at dt = 1 ms on the 57 x 57 and 100 x 100 sheets, with the
# default material and softened to Verlet's threshold of 10 sub-steps.
vbd_section() {
    echo "## vbd at dt = 1 ms, the default scene's material, 2 threads"
    echo
    echo "| sheet | vertices | stiffness scale | Verlet sub-steps per 1 ms | kernels | vbd sweeps | Chebyshev rho | relaxation | wait | wall ms/step | CPU ms/step | run | 2 s run |"
    echo "|---|--:|--:|--:|---|--:|--:|--:|---|--:|--:|---|---|"
    for n in 57 100; do
        sub=$(verlet_substeps --set mesh.nx=$n --set mesh.ny=$n)
        for sweeps in 10 4; do vbd_row $n reference $sweeps $VBD_STEPS; done
        for sweeps in 10 4 2 1; do vbd_row $n fast $sweeps 98; done
        [ $n = 57 ] && accelerated="4 8" || accelerated="12 16"
        for sweeps in $accelerated; do vbd_row $n fast $sweeps 98 0.9; done
        vbd_row $n fast 4 98 0.9 1.3
    done
    echo
    echo "Verlet sub-steps: the fewest of 1, 2, 5, 10, 20, 40, 80 per 1 ms that ran 0.1 s without a"
    echo "vertex running away. Reference rows: 2 + $VBD_STEPS steps timed (the double sweeps of"
    echo "kernels/integrators/vbd.c); fast rows (kernels/integrators/fast_vbd.c): 2 + 98, the whole 0.1 s, and the energies"
    echo "after it finite. 2 s run: the same settings for 2 s, and the most the total energy rose above"
    echo "its start (the sheet falls about 1 J: a rise is stretch the sweeps stored), or where a vertex"
    echo "ran away (fast rows). Chebyshev rho: vbd.chebyshev_rho, 0 = off. Relaxation: vbd.relaxation"
    echo "(each vertex's Newton step times it; 1 = plain). Wait: the team's wait policy (scene key wait;"
    echo "passive, the default, sleeps on a futex at each of a step's barriers, 32 at 4 sweeps and 7"
    echo "colors; spin busy-waits). Stiffness scale 1: the"
    echo "default material. Target: vbd stable at 1 ms where Verlet needs >= 10, below 1 ms a step."
    echo
    echo "### At Verlet's threshold: the material softened until Verlet needs 10 sub-steps per 1 ms"
    echo
    echo "| sheet | vertices | stiffness scale | Verlet sub-steps per 1 ms | kernels | vbd sweeps | Chebyshev rho | relaxation | wait | wall ms/step | CPU ms/step | run | 2 s run |"
    echo "|---|--:|--:|--:|---|--:|--:|--:|---|--:|--:|---|---|"
    for n in 57 100; do
        scale=$(threshold_scale "$n")
        [ "$scale" = none ] && echo "| $n x $n | $((n * n)) | none | - | fast | - | - | - | - | - | - | Verlet ran away at 10 sub-steps on the whole ladder | - |" &&
            continue
        # shellcheck disable=SC2046
        sub=$(verlet_substeps_of "5 6 7 8 9 10 20" --set mesh.nx="$n" --set mesh.ny="$n" $(softened "$scale"))
        [ "$n" = 57 ] && accelerated="3 4" || accelerated="4 5 6"
        # shellcheck disable=SC2046
        for sweeps in 4 2 1; do vbd_row "$n" fast "$sweeps" 98 0 1 "$scale" $(softened "$scale"); done
        # shellcheck disable=SC2046
        for sweeps in $accelerated; do vbd_row "$n" fast "$sweeps" 98 0.9 1 "$scale" $(softened "$scale"); done
        # each vertex's step over-relaxed (vbd.relaxation) besides Chebyshev's acceleration
        [ "$n" = 57 ] && relaxed="3" || relaxed="3 4"
        # shellcheck disable=SC2046
        for sweeps in $relaxed; do vbd_row "$n" fast "$sweeps" 98 0.9 1.3 "$scale" $(softened "$scale"); done
        # the stable relaxed row again with spinning waits (a machine of its own, as a haptic loop has)
        [ "$n" = 57 ] && stable=3 || stable=4
        VBD_WAIT=spin
        # shellcheck disable=SC2046
        vbd_row "$n" fast "$stable" 98 0.9 1.3 "$scale" $(softened "$scale")
        VBD_WAIT=passive
    done
    echo
    echo "Stiffness scale s: the stiffest of 2^(-k/4), k = 0 .. 20, at which Verlet ran the sheet 0.1 s"
    echo "with 10 sub-steps per 1 ms; bond, angle, spring and hinge constants times s, the spring's"
    echo "damping times sqrt(s) (the same damping ratio: unscaled, the damping alone holds the 100 x 100"
    echo "sheet's Verlet to 20 sub-steps). Verlet sub-steps: the fewest of 5, 6, 7, 8, 9, 10, 20 that"
    echo "ran 0.1 s. The rest as above."
}

# ---- implicit_euler on the fast kernels, 100k sheet (issue 16) ----------
# The 100k sheet of bench/bench_cases.c: 316 x 316 vertices over 1 m
# (spacing h = 1/315 m), jitter 0.1, bond k = 100 N/m, angle 0.5 k h² and
# stretch-bend 0.1 k h, 0.1 kg/m², the default terms (no spring, no hinge),
# hung from its top corners under gravity with the default scene's drag.
SHEET_100K="--set mesh.nx=316 --set mesh.ny=316 --set mesh.jitter=0.1 --set bond.k=100 --set angle.k=5.0394e-4
 --set stretch_bend.k=0.031746 --set spring.k=0 --set spring.damping=0 --set bend.k=0 --set density=0.1"

# The same on a finer ladder, for the 100k sheet.
verlet_substeps_fine() { verlet_substeps_of "20 25 30 40 50 60 80" "$@"; }

# The positions after `time` s of steps of dt, an OBJ's vertex lines, into
# file $1, and those at the start into $TMP/start.
positions_at() {
    file=$1 time=$2 dt=$3
    shift 3
    rm -rf "$TMP/pos"
    "$SB" run "$SCENE" --set 'output.formats=[obj]' --output "$TMP/pos" --set duration="$time" \
        --set frame_interval="$time" --set dt="$dt" "$@" >/dev/null 2>&1 || {
        echo "bench/implicit.sh: softbond run $*: failed" >&2
        return 1
    }
    grep '^v ' "$TMP/pos/frame_000000.obj" >"$TMP/start"
    grep '^v ' "$TMP/pos/frame_000001.obj" >"$file"
}

# Max and RMS distance of positions $1 from $2, over the largest distance
# the reference $2 moved from the start $3 (OBJ vertex lines, the same
# order): "max rms".
implicit_position_error() {
    paste -d' ' "$1" "$2" "$3" | awk '{
        d = ($2 - $6)^2 + ($3 - $7)^2 + ($4 - $8)^2; m = ($6 - $10)^2 + ($7 - $11)^2 + ($8 - $12)^2
        if (d > dmax) dmax = d; if (m > mmax) mmax = m; sum += d; n++ }
        END { printf "%.2g %.2g\n", sqrt(dmax / mmax), sqrt(sum / n / mmax) }'
}

implicit_fast_section() {
    steps=$1 accuracy_time=$2
    # shellcheck disable=SC2086
    k=$(verlet_substeps_fine $SHEET_100K --threads 2)
    dt_verlet=$(awk -v k="$k" 'BEGIN { printf "%.6g", 0.001 / k }')
    dt_implicit=$(awk -v d="$dt_verlet" 'BEGIN { printf "%.6g", 10 * d }')
    dt_fine=$(awk -v d="$dt_verlet" 'BEGIN { printf "%.6g", d / 10 }')
    # shellcheck disable=SC2086
    # 100 steps a timed implicit step: /usr/bin/time's 10 ms resolution made 10 too few
    verlet=$(per_step "$dt_verlet" $((100 * steps)) $SHEET_100K --threads 2)
    echo "## implicit_euler on the fast kernels, 100k sheet, 2 threads"
    echo
    echo "The 100k sheet of bench/bench_cases.c (316 x 316, default terms), hung from its top corners."
    echo "Verlet's largest stable step (the fewest of 20, 25, 30, 40, 50, 60, 80 sub-steps per 1 ms that"
    echo "run 0.1 s): $dt_verlet s, $(echo "$verlet" | awk '{print $1}') ms a step (CPU $(echo "$verlet" | awk '{print $2}'))."
    echo "implicit_euler (implicit.solver cg, kernels fast) at 10 x that step, dt = $dt_implicit s, $steps steps;"
    echo "error: the positions after $accuracy_time s against Verlet at dt / 10 = $dt_fine s, the largest"
    echo "vertex distance and the RMS one over the largest distance the reference moved."
    echo
    echo "| integrator | dt s | Newton tolerance | wall ms/step | CPU ms/step | x Verlet step | Newton | CG | unconverged | max error | RMS error |"
    echo "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|"
    # shellcheck disable=SC2086
    positions_at "$TMP/fine" "$accuracy_time" "$dt_fine" $SHEET_100K --threads 2
    # shellcheck disable=SC2086
    positions_at "$TMP/verlet" "$accuracy_time" "$dt_verlet" $SHEET_100K --threads 2
    e=$(implicit_position_error "$TMP/verlet" "$TMP/fine" "$TMP/start")
    echo "| verlet | $dt_verlet | - | ${verlet% *} | ${verlet#* } | 1 | - | - | - | ${e% *} | ${e#* } |"
    for tolerance in 1e-8 1e-3 1e-2; do
        # shellcheck disable=SC2086
        t=$(per_step "$dt_implicit" "$steps" $SHEET_100K --threads 2 --set integrator=implicit_euler \
            --set implicit.solver=cg --set implicit.tolerance=$tolerance)
        w=$(solver_work)
        ratio=$(echo "$t $verlet" | awk '{ printf "%.1f", $1 / $3 }')
        # shellcheck disable=SC2086
        positions_at "$TMP/implicit" "$accuracy_time" "$dt_implicit" $SHEET_100K --threads 2 \
            --set integrator=implicit_euler --set implicit.solver=cg --set implicit.tolerance=$tolerance
        e=$(implicit_position_error "$TMP/implicit" "$TMP/fine" "$TMP/start")
        echo "| implicit_euler | $dt_implicit | $tolerance | ${t% *} | ${t#* } | $ratio |" \
            "$(echo "$w" | awk '{print $1 " | " $2 " | " $3}') | ${e% *} | ${e#* } |"
    done
    echo
    echo "Newton, CG and unconverged: the whole run of 2 + $steps steps. Target: implicit_euler at most"
    echo "10 x a Verlet step per step (x Verlet step <= 10)."
}

# ---- implicit_euler on the default scene (issue 16) ----------------------
default_scene_section() {
    echo "## implicit_euler, default scene (30 x 30 = 900 vertices), dt = 10 ms, $STEPS steps"
    echo
    echo "Each of the two runs timed $DEFAULT_REPEATS times, the least wall and the least CPU time kept."
    echo
    echo "| solver | threads | wall ms/step | CPU ms/step | Newton | CG | unconverged |"
    echo "|---|--:|--:|--:|--:|--:|--:|"
    for solver in cholesky cg; do
        for threads in 1 2; do
            t=$(REPEATS=$DEFAULT_REPEATS per_step 0.01 $STEPS --set integrator=implicit_euler --set implicit.solver=$solver --threads $threads)
            w=$(solver_work)
            echo "| $solver | $threads | ${t% *} | ${t#* } | $(echo "$w" | awk '{print $1}') |" \
                "$(echo "$w" | awk '{print $2}') | $(echo "$w" | awk '{print $3}') |"
        done
    done
    echo
    echo "Newton, CG and unconverged: the whole run of 2 + $STEPS steps. Target: <= 10 ms a step."
    echo
}

# The default scene's rows: 100 steps, the least of 3 runs each (20 steps
# of one run read 27.5 ms a step where whole runs said 16: /usr/bin/time's
# 10 ms resolution and the shared machine's noise over a 0.4 s difference).
STEPS=100
DEFAULT_REPEATS=3
VBD_STEPS=20
# 50 timed steps: over 10 the 10 ms clock resolved a step to about 1 ms and
# only the swing's first steps, which need fewer CG iterations, were timed
IMPLICIT_FAST_STEPS=50
[ $QUICK -eq 1 ] && STEPS=10 && DEFAULT_REPEATS=1 && VBD_STEPS=4 && IMPLICIT_FAST_STEPS=2
if [ $DEFAULT_ONLY -eq 1 ]; then
    echo "$(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git -C "$ROOT" rev-parse --short HEAD)," \
        "load average $(cut -d' ' -f1-3 /proc/loadavg) at the start."
    echo
    default_scene_section
    exit 0
fi
if [ $VBD_ONLY -eq 1 ]; then
    echo "$(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git -C "$ROOT" rev-parse --short HEAD)," \
        "load average $(cut -d' ' -f1-3 /proc/loadavg) at the start."
    echo
    vbd_section
    exit 0
fi
if [ $IMPLICIT_FAST_ONLY -eq 1 ]; then
    echo "$(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git -C "$ROOT" rev-parse --short HEAD)," \
        "load average $(cut -d' ' -f1-3 /proc/loadavg) at the start."
    echo
    implicit_fast_section $IMPLICIT_FAST_STEPS 0.02
    exit 0
fi
{
    echo "# Implicit integrators (issue 16): measured by bench/implicit.sh"
    echo
    echo "$(date -u '+%Y-%m-%d %H:%M UTC'), commit $(git -C "$ROOT" rev-parse --short HEAD)," \
        "$(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg) at the start."
    echo "A step's time: two runs of 2 and 2 + N steps, the difference over N (set-up not counted);"
    echo "wall clock and CPU (user + system, all threads)."
    echo
    default_scene_section
    vbd_section
    T100K=0.02
    dt_v=$(verlet_largest_step)
    echo "## vbd at 10 x Verlet's largest stable step, 317 x 317 sheet (100 489 vertices), 2 threads"
    echo
    if [ "$dt_v" = none ]; then
        echo "Verlet ran away at every step of the grid."
    else
        dt_vbd=$(awk -v d="$dt_v" 'BEGIN { printf "%.6g", 10 * d }')
        dt_fine=$(awk -v d="$dt_v" 'BEGIN { printf "%.6g", d / 4 }')
        n_v=$(awk -v d="$dt_v" 'BEGIN { printf "%d", 0.01 / d }')
        final_positions fine --set dt="$dt_fine"
        final_positions verlet --set dt="$dt_v"
        echo "| integrator | dt | sweeps | wall ms/step | CPU ms/step | x a Verlet step | RMS error | max error |"
        echo "|---|--:|--:|--:|--:|--:|--:|--:|"
        tv=$(per_step "$dt_v" "$n_v" --set mesh.nx=317 --set mesh.ny=317 --threads 2)
        e=$(position_error verlet fine)
        echo "| verlet | $dt_v | - | ${tv% *} | ${tv#* } | 1 | $(echo "$e" | cut -d' ' -f1) m | $(echo "$e" | cut -d' ' -f2) m |"
        for sweeps in 1 2 4; do
            if final_positions vbd --set integrator=vbd --set vbd.iterations=$sweeps --set dt="$dt_vbd" &&
                t=$(per_step "$dt_vbd" 40 --set integrator=vbd --set vbd.iterations=$sweeps \
                    --set mesh.nx=317 --set mesh.ny=317 --threads 2 2>/dev/null); then
                e=$(position_error vbd fine)
                ratio=$(awk -v a="${t% *}" -v b="${tv% *}" 'BEGIN { printf "%.1f", a / b }')
                echo "| vbd | $dt_vbd | $sweeps | ${t% *} | ${t#* } | $ratio | $(echo "$e" | cut -d' ' -f1) m |" \
                    "$(echo "$e" | cut -d' ' -f2) m |"
            else
                echo "| vbd | $dt_vbd | $sweeps | - | - | - | failed | |"
            fi
        done
        echo
        echo "Verlet's largest stable step: the largest of $VERLET_GRID s that ran 0.02 s."
        echo "Errors: positions after $T100K s against Verlet at"
        echo "dt = $dt_fine s (a quarter of its stable step), over the 100 489 vertices; the sheet moved"
        echo "$(echo "$e" | cut -d' ' -f3) m (RMS) in that time. Target: vbd at most 10 x a Verlet step."
    fi
    echo
    implicit_fast_section $IMPLICIT_FAST_STEPS 0.02
} >"$OUT"
cat "$OUT"
