#!/bin/sh
# The contact benchmark: builds Release and runs sb_bench_contact, which
# times the 100k sheet with and without a plane and a sphere, and with them and
# self-contact (a sheet draped
# over the sphere, and a sheet lying on the floor), on 1 and 2 threads.
# Writes bench/results/contact.csv and contact.md. About 2 minutes.
#
#   bench/contact.sh [sb_bench_contact options]
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$ROOT/build
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target sb_bench_contact
cd "$ROOT"
"$BUILD/bench/sb_bench_contact" --csv bench/results/contact.csv --md bench/results/contact.md "$@"
