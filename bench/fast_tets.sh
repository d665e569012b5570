#!/bin/bash
# The co-rotated tetrahedra's fast pass before and after a change, on the
# syringe's body (1892 vertices, 6195 linear tetrahedra): two `softbond`
# programs run interleaved on scenes/corotated_body.yaml and on
# scenes/syringe.yaml with tissue.model=corotated, 1 thread, --no-realtime,
# 1 step and 2000 steps, three times each; prints one line a run:
#   scene program steps wall_s user_s sys_s load_1min
# The CPU time of a step is (user + sys at 2000 − at 1) / 1999, which a busy
# machine's wall clock does not give (bench/results/fast_tets.md).
#
#   bench/fast_tets.sh BEFORE/softbond AFTER/softbond
set -eu
[ $# -eq 2 ] || { echo "usage: bench/fast_tets.sh BEFORE/softbond AFTER/softbond" >&2; exit 2; }
SCENES=$(cd "$(dirname "$0")/../scenes" && pwd)
OUT=$(mktemp -d)
trap 'rm -rf "$OUT"' EXIT
TIMEFORMAT='%R %U %S'
cd "$SCENES"
for rep in 1 2 3; do
    for scene in body syringe; do
        for steps in 1 2000; do
            if [ $scene = body ]; then
                args=(corotated_body.yaml --set "duration=$(awk "BEGIN { print $steps * 0.0001 }")")
            else
                args=(syringe.yaml --set tissue.model=corotated --set "duration=$(awk "BEGIN { print $steps * 0.00005 }")")
            fi
            for program in before after; do
                binary=$1
                [ $program = after ] && binary=$2
                t=$({ time "$binary" run "${args[@]}" --no-realtime --threads 1 --output "$OUT" >/dev/null 2>&1; } 2>&1)
                echo "$scene $program $steps $t $(cut -d' ' -f1 /proc/loadavg)"
            done
        done
    done
done
