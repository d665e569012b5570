#!/bin/sh
# Fuzzes softbond's parsers with clang's libFuzzer, each harness for a given
# time (tests/fuzz/entries.c: scene_yaml, scene_set, obj, off, irit, pov,
# tetgen, gmsh, positions_csv, haptics_csv, assimp_ply), under the address and
# undefined-behaviour sanitizers:
#
#   tests/fuzz/run.sh SECONDS [HARNESS...] [--build DIR]
#
# Builds DIR (default build-fuzz) with clang and -DSB_FUZZ=ON, then runs
# each harness (all by default) for SECONDS from the committed corpus
# tests/fuzz/corpus/HARNESS (read only: what the fuzzer adds goes to
# DIR/fuzz-corpus/HARNESS). An input that crashes, leaks, trips a
# sanitizer or runs over 10 s (45 s for assimp_ply, whose importer child
# has 30 s) is written to DIR/fuzz-findings/HARNESS/;
# once the parser is fixed, copy it into tests/fuzz/corpus/HARNESS/, where
# the ctest fuzz_replay (`make test`) replays it for ever. Prints one line
# per harness: its executions and findings. Needs clang and libFuzzer
# (Debian: apt-get install clang libclang-rt-14-dev); `make test` does not.
set -eu
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
BUILD=$ROOT/build-fuzz
SECONDS_EACH=
HARNESSES=
while [ $# -gt 0 ]; do
    case $1 in
        --build) BUILD=$2; shift 2 ;;
        -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
        -*) echo "tests/fuzz/run.sh: unknown option $1" >&2; exit 2 ;;
        *) if [ -z "$SECONDS_EACH" ]; then SECONDS_EACH=$1; else HARNESSES="$HARNESSES $1"; fi; shift ;;
    esac
done
if [ -z "$SECONDS_EACH" ]; then sed -n '2,20p' "$0" >&2; exit 2; fi
[ -n "$HARNESSES" ] || HARNESSES=$(ls "$ROOT/tests/fuzz/corpus")
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_C_COMPILER=clang -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DSB_SANITIZE=ON -DSB_FUZZ=ON >/dev/null
targets=""
for h in $HARNESSES; do targets="$targets fuzz_$h"; done
cmake --build "$BUILD" -j "${JOBS:-2}" --target $targets >/dev/null
status=0
for h in $HARNESSES; do
    work=$BUILD/fuzz-corpus/$h
    findings=$BUILD/fuzz-findings/$h
    mkdir -p "$work" "$findings"
    log=$BUILD/fuzz-$h.log
    # the isolated importer kills its child after 30 s: past that is a hang of softbond's own
    timeout=10
    [ "$h" = assimp_ply ] && timeout=45
    ASAN_OPTIONS=detect_leaks=1 "$BUILD/tests/fuzz/fuzz_$h" -max_total_time="$SECONDS_EACH" -timeout=$timeout \
        -rss_limit_mb=2560 -print_final_stats=1 -artifact_prefix="$findings/" \
        "$work" "$ROOT/tests/fuzz/corpus/$h" >"$log" 2>&1 || status=1
    runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -n 1)
    found=$(ls "$findings" | wc -l)
    echo "$h: ${runs:-?} executions in $SECONDS_EACH s, $found findings (log: $log)"
    [ "$found" -eq 0 ] || status=1
done
exit $status
