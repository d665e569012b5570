#!/usr/bin/env bash
# How long `make test` takes, test by test: builds its four configurations
# as the Makefile does (build, build-double, build-asan, build-tsan, with
# its options and labels) and runs each test alone, one at a time (ctest -R
# '^name$'), recording the wall time and the processor time of the test and
# its children (user + system, what bash's `time` reports: on a shared
# machine the processor time is the steadier figure, the wall time grows
# with the load). Writes bench/results/test_times.csv anew
# (config,test,wall_s,user_s,sys_s) and prints each configuration's totals
# with the load average.
#
#   bench/test_times.sh [config ...]     (default: float double asan tsan)
#   ONLY='test_fast|test_cli' bench/test_times.sh ...   (only the tests whose names match)
set -euo pipefail
cd "$(dirname "$0")/.."
out=bench/results/test_times.csv
configs=("${@:-float double asan tsan}")
read -r -a configs <<<"${configs[*]}"
echo "config,test,wall_s,user_s,sys_s" >"$out"

configure() { # config -> build dir, cmake options, ctest selection, environment
    case $1 in
    float) dir=build opts="-DCMAKE_BUILD_TYPE=Release" select="-LE fuzz" env="" ;;
    double) dir=build-double opts="-DCMAKE_BUILD_TYPE=Release -DSB_DOUBLE=ON" select="-LE fuzz" env="" ;;
    asan) dir=build-asan opts="-DCMAKE_BUILD_TYPE=RelWithDebInfo -DSB_SANITIZE=ON" select="-LE no_sanitizer" \
        env="ASAN_OPTIONS=detect_leaks=1" ;;
    tsan) dir=build-tsan opts="-DCMAKE_BUILD_TYPE=RelWithDebInfo -DSB_SANITIZE_THREAD=ON" select="-L thread" \
        env="TSAN_OPTIONS=halt_on_error=1" ;;
    *) echo "unknown configuration $1 (float, double, asan, tsan)" >&2 && exit 2 ;;
    esac
}

TIMEFORMAT='%R %U %S'
for config in "${configs[@]}"; do
    configure "$config"
    # shellcheck disable=SC2086
    cmake -S . -B "$dir" $opts >/dev/null
    targets=()
    [ "$config" = tsan ] && targets=(--target test_runtime test_contact test_self_contact test_haptics_buffer)
    cmake --build "$dir" -j 2 "${targets[@]}" >/dev/null
    wall=0 cpu=0
    # shellcheck disable=SC2086
    for test in $(cd "$dir" && ctest -N $select -R "${ONLY:-.}" | sed -n 's/^ *Test *#[0-9]*: *//p'); do
        # shellcheck disable=SC2086
        times=$({ time (cd "$dir" && env $env ctest -R "^$test\$" $select >/dev/null 2>&1 ||
            echo "softbond: $config: $test failed" >&2); } 2>&1)
        read -r w u s <<<"${times##*$'\n'}"
        echo "$config,$test,$w,$u,$s" >>"$out"
        wall=$(awk "BEGIN { print $wall + $w }") cpu=$(awk "BEGIN { print $cpu + $u + $s }")
    done
    echo "$config: $wall s wall, $cpu s processor, one test at a time (load $(cut -d' ' -f1-3 /proc/loadavg))"
done
