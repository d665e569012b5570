#!/bin/sh
# The Jolt peer of softbond's xpbd (issue 15): the 100 x 100 sheet hanging
# from two corners, 5 iterations, dt 1 ms, in Jolt Physics' WebAssembly
# build on Node.js (bench/jolt/cloth.mjs: one thread, 39 402 stretch and
# shear edge constraints) beside softbond's xpbd with the fast kernels
# (bench/bench_pbd.c: 29 601 bonds alone, and with the angle term's 58 806
# corners; 1 and 2 threads), in one run: the two programs take turns,
# --rounds times, each round one measurement of --steps steps of each; the
# best of the rounds counts.
#
#   bench/jolt/run.sh [--rounds 5] [--steps 400] [--build DIR]
#
# Writes bench/results/pbd_peer.csv and pbd_peer.md (ns per projection of
# each kind, the targets). Installs the npm package (npm ci in bench/jolt,
# from package-lock.json) when it is missing; needs node and npm. Not part
# of `make test`.
set -eu

ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=$ROOT/build
ROUNDS=5
STEPS=400
while [ $# -gt 0 ]; do
    case $1 in
        --rounds) ROUNDS=$2; shift 2 ;;
        --steps) STEPS=$2; shift 2 ;;
        --build) BUILD=$2; shift 2 ;;
        -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
        *) echo "bench/jolt/run.sh: unknown option $1" >&2; exit 2 ;;
    esac
done
JOLT=$ROOT/bench/jolt
RESULTS=$ROOT/bench/results
CSV=$RESULTS/pbd_peer.csv
MD=$RESULTS/pbd_peer.md

if ! command -v node >/dev/null 2>&1 || ! command -v npm >/dev/null 2>&1; then
    echo "bench/jolt/run.sh: node and npm are missing (Debian: apt-get install nodejs npm)" >&2
    exit 1
fi
if [ ! -d "$JOLT/node_modules/jolt-physics" ]; then
    echo "== npm ci (jolt-physics) in $JOLT"
    (cd "$JOLT" && npm ci --no-audit --no-fund >/dev/null)
fi
echo "== build (Release) in $BUILD"
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j 2 --target sb_bench_pbd >/dev/null

RAW=$(mktemp)
trap 'rm -f "$RAW"' EXIT
LOAD_BEFORE=$(cut -d' ' -f1-3 /proc/loadavg)
round=1
while [ "$round" -le "$ROUNDS" ]; do
    echo "== round $round of $ROUNDS"
    "$BUILD/bench/sb_bench_pbd" --steps "$STEPS" --repeats 1 | tee -a "$RAW"
    node "$JOLT/cloth.mjs" --steps "$STEPS" --repeats 1 | tee -a "$RAW"
    round=$((round + 1))
done
LOAD_AFTER=$(cut -d' ' -f1-3 /proc/loadavg)

# The best time of each peer, case and thread count; ns per projection:
# bonds (or Jolt's edges) from the bonds row, corners from the difference
# of the corners and bonds rows at the same thread count.
awk -F, -v csv="$CSV" -v md="$MD" -v rounds="$ROUNDS" -v steps="$STEPS" \
    -v cpu="$(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')" \
    -v commit="$(git -C "$ROOT" rev-parse --short HEAD)" -v date="$(date -u '+%Y-%m-%d %H:%M UTC')" \
    -v load="$LOAD_BEFORE before, $LOAD_AFTER after" '
{
    key = $1 "," $2 "," $3
    if (!(key in best) || $5 < best[key]) best[key] = $5
    bonds[key] = $6; corners[key] = $7; barriers[key] = $8
    if (!(key in order)) { order[key] = ++n; keys[n] = key }
}
END {
    print "peer,case,threads,steps,ms_per_step,bond_projections,corner_projections,ns_per_bond_projection,ns_per_corner_projection,barriers_per_step" > csv
    for (i = 1; i <= n; i++) {
        k = keys[i]; split(k, f, ",")
        bond_ns = 1e6 * best[k] / bonds[k]; corner_ns = ""
        if (f[2] == "corners") {
            b = f[1] ",bonds," f[3]
            bond_ns = 1e6 * best[b] / bonds[b]
            corner_ns = sprintf("%.2f", 1e6 * (best[k] - best[b]) / corners[k])
        }
        printf "%s,%d,%.4f,%d,%d,%.2f,%s,%s\n", k, steps, best[k], bonds[k], corners[k], bond_ns, corner_ns, barriers[k] >> csv
        ns[k] = bond_ns; cns[k] = corner_ns
    }
    jolt = best["jolt,bonds,1"]; jns = ns["jolt,bonds,1"]
    b1 = best["softbond,bonds,1"]; b2 = best["softbond,bonds,2"]; c1 = best["softbond,corners,1"]; c2 = best["softbond,corners,2"]
    print "# xpbd against the Jolt peer (bench/jolt/run.sh)\n" > md
    printf "The 100 x 100 sheet hanging from two corners, 5 iterations, dt 1 ms; best of %d rounds of %d steps, the peers taking turns. %s, commit %s, %s; load average %s (2 logical cores).\n\n", rounds, steps, date, commit, cpu, load >> md
    print "| peer | constraints | threads | ms a step | ns a bond (edge) projection | ns a corner projection |" >> md
    print "|---|---|---|---|---|---|" >> md
    for (i = 1; i <= n; i++) {
        k = keys[i]; split(k, f, ",")
        what = f[1] == "jolt" ? "39 402 edges (stretch, shear)" : f[2] == "bonds" ? "29 601 bonds" : "29 601 bonds + 58 806 corners"
        printf "| %s | %s | %s | %.3f | %.2f | %s |\n", f[1], what, f[3], best[k], ns[k], cns[k] == "" ? "" : cns[k] >> md
    }
    split(load, l, " ")
    if (l[1] > 2) print "\nThe machine was shared (load above its 2 cores): a second thread waits at every barrier for a core, so the 2-thread figures are the load'"'"'s, not the code'"'"'s." >> md
    print "\nIssue 15'"'"'s targets:\n" >> md
    printf "- bonds alone, 1 thread: %.2f ns a projection, %.2f x Jolt'"'"'s %.2f (target at most 0.5 x)\n", ns["softbond,bonds,1"], ns["softbond,bonds,1"] / jns, jns >> md
    printf "- bonds alone, 2 threads: %.2f x faster than 1 thread (target at least 1.8 x), %d barriers a step; with the corners %.2f x, %d barriers\n", b1 / b2, barriers["softbond,bonds,2"], c1 / c2, barriers["softbond,corners,2"] >> md
    printf "- with the corners: a step %.2f x the bonds-alone step on 1 thread, %.2f x on 2 (target at most 2 x)\n", c1 / b1, c2 / b2 >> md
}' "$RAW"
echo "== wrote $CSV and $MD"
cat "$MD"
