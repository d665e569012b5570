#!/bin/sh
# The speed-accuracy chart of the tissue models (issue 29) in one command:
# builds sb_bench_materials in build/ (Release, the shipped float fast
# kernels), runs it (ccx must be on PATH: Debian's calculix-ccx), draws the
# chart with bench/materials_chart.gp and writes materials_chart.md (the
# command, the date, the machine's load, the table) in bench/results.
#
#   bench/materials_chart.sh
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$ROOT/build
RESULTS=$ROOT/bench/results
command -v ccx >/dev/null 2>&1 || { echo "bench/materials_chart.sh: ccx (calculix-ccx) not found" >&2; exit 1; }
command -v gnuplot >/dev/null 2>&1 || { echo "bench/materials_chart.sh: gnuplot not found" >&2; exit 1; }
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target sb_bench_materials >/dev/null
load_before=$(uptime)
"$BUILD/bench/sb_bench_materials" "$RESULTS"
load_after=$(uptime)
cd "$ROOT" && gnuplot bench/materials_chart.gp
{
    echo "# Speed-accuracy of the tissue models (issue 29)"
    echo
    echo "Made by \`bench/materials_chart.sh\` (\`sb_bench_materials\`, bench/bench_materials.c;"
    echo "chart by bench/materials_chart.gp) on $(date -u '+%Y-%m-%d %H:%M UTC'),"
    echo "$(nproc) cores ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ *//')),"
    echo "commit $(git -C "$ROOT" rev-parse --short HEAD 2>/dev/null || echo unknown)."
    echo "Load: before \`$(echo "$load_before" | sed 's/.*load/load/')\`, after \`$(echo "$load_after" | sed 's/.*load/load/')\`."
    echo
    echo "$(grep -m1 '^#' "$RESULTS/materials_chart.csv" | sed 's/^# //')."
    echo
    echo "| case | model | cells across | vertices | error % | stable dt (s) | µs a step | ms a simulated s |"
    echo "|---|---|---|---|---|---|---|---|"
    awk -F, '!/^#/ && NR > 2 { printf "| %s | %s | %s | %s | %+.2f | %s | %s | %s |\n", $1, $2, $3, $4, $6, $7, $8, $9 }' \
        "$RESULTS/materials_chart.csv"
    echo
    echo "![speed-accuracy](materials_chart.png)"
} > "$RESULTS/materials_chart.md"
echo "bench/materials_chart.sh: results in $RESULTS/materials_chart.{csv,png,md}"
