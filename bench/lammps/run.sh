#!/bin/sh
# The LAMMPS peer: the same meshes, bond stretch and angle bend, gravity and
# NVE (velocity Verlet), timed by LAMMPS' own "Loop time" line, with 1 worker
# (lmp) and 2 (mpirun -np 2 lmp; Debian's LAMMPS has no OpenMP styles).
#
#   bench/lammps/run.sh [--cases small|all|NAME,NAME] [--build DIR] [--steps N] [--all-terms]
#
# Writes bench/results/lammps.csv (--all-terms: lammps_all_terms.csv).
# Installs lammps and openmpi-bin when they are missing (as root). Not part
# of `make test`.
#
# Steps: the step count of sb_bench's fast 2-thread row for the case in
# bench/results/throughput.csv (so both run the same number of steps), else
# the reference row's, else 2000 / 200 / 20 by size; at least
# LAMMPS_MIN_STEPS (default 20, so that LAMMPS' loop time is not a couple of
# steps) and at most LAMMPS_MAX_STEPS (default 20000); --steps N overrides.
#
# Model, per case (see bench/lammps/export_data.c for the data file):
#   units si; atom_style angle; pair_style none; special_bonds lj/coul 0 0 0
#   bond_style harmonic, K = kb/2;  angle_style cosine/squared, K = kθ/2
#   fix nve + fix gravity on every atom but the pinned ones
# Sheets are exported without jitter (LAMMPS takes r0 and θ0 per type; an
# unjittered sheet has 2 bond and 2 angle types, a jittered one would need a
# type per bond). The peer has no stretch-bend term: softbond's step does
# more work than LAMMPS' here.
#
# --all-terms: sb_bench --all-terms' model and time step (sheets only: the
# hinge table assumes a flat rest), against throughput_all_terms.csv:
#   atom_style molecular; bond_style harmonic, K = (kb + ks)/2 (the damped
#   spring's elastic part; its damping has no LAMMPS bond style);
#   dihedral_style table spline 3600, one dihedral o0 e0 e1 o1 per interior
#   edge, tabulating ½ k_bend (π − |φ_L|)² (softbond's ½ k (φ − φ0)² with
#   φ0 = 0 in LAMMPS' angle, 180° when flat: see export_data.c).
# Before timing a case, LAMMPS evaluates a bent copy of it (run 0) and its
# bond, angle and dihedral energies must match softbond's reference within
# a relative ENERGY_TOLERANCE (1e-6; they agree to ~1e-13), else the script
# stops with the figures.
set -eu

ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=$ROOT/build
CASES=all
STEPS=
ALL_TERMS=
MAX_STEPS=${LAMMPS_MAX_STEPS:-20000}
MIN_STEPS=${LAMMPS_MIN_STEPS:-20}
while [ $# -gt 0 ]; do
    case $1 in
        --cases) CASES=$2; shift 2 ;;
        --build) BUILD=$2; shift 2 ;;
        --steps) STEPS=$2; shift 2 ;;
        --all-terms) ALL_TERMS=yes; shift ;;
        -h|--help) sed -n '2,37p' "$0"; exit 0 ;;
        *) echo "bench/lammps/run.sh: unknown option $1" >&2; exit 2 ;;
    esac
done

mkdir -p "$BUILD"
BUILD=$(cd "$BUILD" && pwd)
RESULTS=$ROOT/bench/results
SUFFIX=${ALL_TERMS:+_all_terms}
THROUGHPUT=$RESULTS/throughput$SUFFIX.csv
ENERGY_TOLERANCE=1e-6
WORK=$BUILD/bench-lammps
EXPORT=$BUILD/bench/sb_lammps_export

# ---- dependencies ------------------------------------------------------------
find_lmp() {
    for name in lmp lmp_serial lmp_mpi lmp_openmpi; do
        if command -v "$name" >/dev/null 2>&1; then echo "$name"; return 0; fi
    done
    return 1
}
if ! find_lmp >/dev/null || ! command -v mpirun >/dev/null 2>&1; then
    if [ "$(id -u)" -ne 0 ]; then
        echo "bench/lammps/run.sh: lammps and openmpi-bin are missing; run as root to install them" >&2
        exit 1
    fi
    echo "installing lammps and openmpi-bin" >&2
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq lammps openmpi-bin >/dev/null
fi
LMP=$(find_lmp)
if [ ! -x "$EXPORT" ]; then
    echo "bench/lammps/run.sh: $EXPORT is missing; build first (cmake --build $BUILD --target sb_lammps_export)" >&2
    exit 1
fi

case $CASES in
    all) CASES="sheet_10k icosphere_10k sheet_100k icosphere_164k sheet_1m icosphere_655k" ;;
    small) CASES="sheet_10k icosphere_10k" ;;
    *) CASES=$(echo "$CASES" | tr ',' ' ') ;;
esac
if [ -n "$ALL_TERMS" ]; then # the hinge table needs a flat rest: sheets only
    CASES=$(for c in $CASES; do case $c in sheet_*) echo "$c" ;; esac; done)
fi
case $CASES in
    "") echo "bench/lammps/run.sh: no case to run" >&2; exit 2 ;;
esac

# ---- helpers ---------------------------------------------------------------
# softbond's row for a case: $1 case, $2 kernels, $3 threads, $4 column
# (12 = steps, 14 = ns_per_step); empty when absent or failed.
softbond_value() {
    [ -f "$THROUGHPUT" ] || return 0
    awk -F, -v c="$1" -v k="$2" -v t="$3" -v col="$4" \
        '!/^#/ && $1 == c && $10 == k && $11 == t && $14 != "" { print $col; exit }' "$THROUGHPUT"
}

steps_for() {
    if [ -n "$STEPS" ]; then echo "$STEPS"; return; fi
    n=$(softbond_value "$1" fast 2 12)
    [ -n "$n" ] || n=$(softbond_value "$1" reference 1 12)
    if [ -z "$n" ]; then
        case $1 in
            *_10k) n=2000 ;;
            *_100k|*_164k) n=200 ;;
            *) n=20 ;;
        esac
    fi
    [ "$n" -ge "$MIN_STEPS" ] || n=$MIN_STEPS
    [ "$n" -le "$MAX_STEPS" ] || n=$MAX_STEPS
    echo "$n"
}

# The styles and the data file: $1 data file.
write_model() {
    if [ -n "$ALL_TERMS" ]; then atom_style=molecular; else atom_style=angle; fi
    cat <<EOF
units           si
atom_style      $atom_style
boundary        m m m
atom_modify     map array
pair_style      none
bond_style      harmonic
angle_style     cosine/squared
EOF
    [ -z "$ALL_TERMS" ] || echo "dihedral_style  table spline 3600"
    cat <<EOF
special_bonds   lj/coul 0.0 0.0 0.0
read_data       $1
EOF
}

write_input() { # $1 case
    terms="ebond eangle${ALL_TERMS:+ edihed}"
    {
        echo "# generated by bench/lammps/run.sh: softbond benchmark case $1"
        write_model "$1.data"
        cat <<EOF
include         $1.settings
comm_modify     cutoff \${sb_cutoff}
neighbor        \${sb_skin} bin
neigh_modify    every 1 delay 0 check yes
timestep        \${sb_dt}
fix             integrate mobile nve
fix             fall mobile gravity \${sb_gravity} vector 0 0 -1
thermo_style    custom step pe $terms ke
thermo          \${steps}
run             \${steps}
EOF
    } >"$WORK/$1.in"
}

# The energy check of --all-terms: $1 case, $2 the exporter's output (its
# "bent" line has softbond's energies). LAMMPS evaluates $1.bent.data once
# (run 0); each of bond, angle and dihedral must agree within
# ENERGY_TOLERANCE of softbond's, relatively, or the script stops.
check_energies() {
    {
        echo "# generated by bench/lammps/run.sh: the energy check of case $1"
        write_model "$1.bent.data"
        cat <<EOF
include         $1.settings
thermo_style    custom step ebond eangle edihed
thermo_modify   format float %.17g
run             0
EOF
    } >"$WORK/$1.check.in"
    log=$WORK/$1.check.log
    (cd "$WORK" && "$LMP" -in "$1.check.in" -log "$log" -screen none)
    theirs=$(awk '$1 == "Step" { getline; print $2, $3, $4; exit }' "$log")
    ours=$(echo "$2" | sed -n 's/.*bond=\([^ ]*\) angle=\([^ ]*\) dihedral=\([^ ]*\).*/\1 \2 \3/p')
    echo "$ours $theirs" | awk -v c="$1" -v tol="$ENERGY_TOLERANCE" '{
        split("bond angle dihedral", name, " ")
        bad = (NF != 6)
        for (i = 1; i <= 3 && !bad; i++) {
            d = $i - $(i + 3); if (d < 0) d = -d
            s = $i < 0 ? -$i : $i
            printf "%s bent: %s energy softbond %.12g J, LAMMPS %.12g J, relative difference %.2g\n", c, name[i], $i, $(i + 3), d / s
            if (!(d <= tol * s)) bad = 1
        }
        exit bad
    }' || {
        echo "bench/lammps/run.sh: $1: LAMMPS' energies of the bent sheet differ from softbond's by more than $ENERGY_TOLERANCE (see $log); not timing it" >&2
        exit 1
    }
}

# Runs LAMMPS: $1 case, $2 workers, $3 steps; prints the loop time in seconds.
run_lammps() {
    log=$WORK/$1.w$2.log
    if [ "$2" -eq 1 ]; then
        (cd "$WORK" && "$LMP" -in "$1.in" -var steps "$3" -log "$log" -screen none)
    else
        (cd "$WORK" && mpirun --allow-run-as-root --mca btl_vader_single_copy_mechanism none -np "$2" \
            "$LMP" -in "$1.in" -var steps "$3" -log "$log" -screen none)
    fi
    awk '/^Loop time of/ { t = $4 } /CPU use with/ { sub("%", "", $1); u = $1 } END { if (t != "") print t, u }' "$log"
}

# ---- run ---------------------------------------------------------------------
mkdir -p "$WORK" "$RESULTS"
CSV=$RESULTS/lammps$SUFFIX.csv
VERSION=$("$LMP" -h 2>/dev/null | sed -n 's/^Large-scale Atomic[^-]* - //p' | head -n 1)
{
    if [ -n "$ALL_TERMS" ]; then
        echo "# LAMMPS peer, all terms (bench/lammps/run.sh --all-terms): bond_style harmonic with K = (kb + ks)/2 + angle_style cosine/squared + dihedral_style table (the hinge), pair_style none, fix nve + gravity"
        echo "# LAMMPS with the terms it has: no stretch-bend and no spring damping (softbond's step computes both); energies of a bent copy of each case checked against softbond's reference before timing (tolerance $ENERGY_TOLERANCE)"
    else
        echo "# LAMMPS peer (bench/lammps/run.sh): bond_style harmonic + angle_style cosine/squared, pair_style none, fix nve + gravity"
    fi
    echo "# lammps: $LMP, ${VERSION:-version unknown} ($(dpkg-query -W -f '${Version}' lammps 2>/dev/null || echo unknown)); mpirun: $(mpirun --version 2>/dev/null | head -n 1)"
    echo "# cpu: $(awk -F': ' '/^model name/ { print $2; exit }' /proc/cpuinfo); logical cores: $(nproc)"
    echo "# sheets without jitter; no stretch-bend term (softbond's step includes it); softbond columns: the fast kernels with threads = workers from $(basename "$THROUGHPUT")"
    echo "# cpu_use_percent: LAMMPS' own figure per worker; well below 100 means the cores were shared and the time is inflated"
    echo "# load average at the start (1, 5, 15 min): $(cut -d ' ' -f 1-3 /proc/loadavg)"
    echo "case,vertices,workers,steps,seconds,ns_per_step,steps_per_s,cpu_use_percent,bond_types,angle_types,softbond_ns_per_step,softbond_speedup"
} >"$CSV"

for c in $CASES; do
    info=$("$EXPORT" --jitter 0 ${ALL_TERMS:+--all-terms} "$c" "$WORK")
    [ -z "$ALL_TERMS" ] || check_energies "$c" "$info"
    summary=$(echo "$info" | tail -n 1)
    vertices=$(echo "$summary" | sed 's/.*vertices=\([0-9]*\).*/\1/')
    btypes=$(echo "$summary" | sed 's/.*bond_types=\([0-9]*\).*/\1/')
    atypes=$(echo "$summary" | sed 's/.*angle_types=\([0-9]*\).*/\1/')
    write_input "$c"
    steps=$(steps_for "$c")
    for workers in 1 2; do
        timing=$(run_lammps "$c" "$workers" "$steps" || true)
        seconds=${timing% *}
        cpu=${timing#* }
        if [ -z "$timing" ]; then
            echo "$c: LAMMPS with $workers worker(s) failed; see $WORK/$c.w$workers.log" >&2
            continue
        fi
        ours=$(softbond_value "$c" fast "$workers" 14)
        echo "$c $vertices $workers $steps $seconds $cpu $btypes $atypes ${ours:-}" | awk '{
            ns = 1e9 * $5 / $4
            ratio = ($9 != "") ? sprintf("%.3f", ns / $9) : ""
            printf "%s,%s,%s,%s,%s,%.1f,%.2f,%s,%s,%s,%s,%s\n", $1, $2, $3, $4, $5, ns, $4 / $5, $6, $7, $8, $9, ratio
        }' | tee -a "$CSV"
    done
done
echo "wrote $CSV"
