#!/bin/sh
# The viewer benchmark: builds Release and runs sb_bench_viewer under Xvfb
# on the default scene's sheet at 317 x 317 = 100 489 vertices (bonds
# 50 N/m, angles 0.3 J, 1 g a vertex, dt 0.1 ms, held at two corners),
# with 1 solver thread and the render thread without a limit
# (--render-share 1), then within its default share (0.15) with 1 and 2
# solver threads, then at 100 x 100: the solver's steps per second alone
# and while `softbond view` draws it (up to 60 frames per second), the
# frame time and the frame rate reached.
#
#   bench/viewer.sh [--build DIR] [--seconds S]
#
# Writes bench/results/viewer.csv and, with the load averages before and
# after, bench/results/viewer.md (the notes below its table are kept).
set -eu
. "$(dirname "$0")/common.sh"

BUILD=$ROOT/build
SECONDS_EACH=10
while [ $# -gt 0 ]; do
    case $1 in
        --build) BUILD=$2; shift 2 ;;
        --seconds) SECONDS_EACH=$2; shift 2 ;;
        -h|--help) sed -n '2,14p' "$0"; exit 0 ;;
        *) echo "bench/viewer.sh: unknown option $1" >&2; exit 2 ;;
    esac
done
bench_build "$BUILD" sb_bench_viewer

before=$(cut -d' ' -f1-3 /proc/loadavg)
csv=$RESULTS/viewer.csv
: > "$csv.tmp"
# side, solver threads, render share
for config in "317 1 1" "317 1 0.15" "317 2 0.15" "100 1 0.15"; do
    set -- $config
    echo "== $1 x $1, $2 solver thread(s), render share $3, $SECONDS_EACH s each"
    xvfb-run -a -s "-screen 0 1280x1024x24" "$BUILD/bench/sb_bench_viewer" "$ROOT/scenes/default.yaml" \
        --seconds "$SECONDS_EACH" --threads "$2" --render-share "$3" --set mesh.nx=$1 --set mesh.ny=$1 \
        --set bond.k=50 --set spring.k=0 --set angle.k=0.3 --set density=0 --set mass=0.001 \
        --set duration=1000 >"$csv.row"
    if [ ! -s "$csv.tmp" ]; then head -1 "$csv.row" > "$csv.tmp"; fi
    tail -1 "$csv.row" >> "$csv.tmp"
done
rm -f "$csv.row"
mv "$csv.tmp" "$csv"
after=$(cut -d' ' -f1-3 /proc/loadavg)
cat "$csv"

md=$RESULTS/viewer.md
notes=""
if [ -f "$md" ]; then notes=$(sed -n '/^## Notes/,$p' "$md"); fi
{
    echo "# The viewer's cost to the solver (bench/viewer.sh)"
    echo
    echo "Measured $(date -u +%Y-%m-%d) on $(nproc) cores; load average before $before, after $after."
    echo
    echo "| vertices | solver threads | render share | steps/s alone | steps/s with the viewer | ratio | frame time, ms | frames/s |"
    echo "|---|---|---|---|---|---|---|---|"
    tail -n +2 "$csv" | awk -F, '{printf "| %s | %s | %s | %s | %s | %s | %s | %s |\n", $1, $2, $3, $4, $5, $6, $7, $8}'
    echo
    if [ -n "$notes" ]; then echo "$notes"; fi
} > "$md"
echo "== wrote $csv and $md"
