#!/bin/sh
# The contact benchmark: builds Release and runs sb_bench_contact, which
# times the 100k sheet without colliders, with a plane and a sphere, with the
# sphere answering vertices only (the face-contact pass's share of a step)
# and with them and self-contact, in three scenes (draped over the sphere,
# lying on the floor, resting on a 1 mm sphere between vertices: face
# contact), on 1 and 2 threads, the ratio of each to the step without
# contact. Writes bench/results/contact.csv and contact.md, with the load
# average at the start and the end. About 4 minutes on a quiet machine.
#
#   bench/contact.sh [sb_bench_contact options]
set -eu
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$ROOT/build
cmake -S "$ROOT" -B "$BUILD" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$BUILD" -j "$(nproc)" --target sb_bench_contact
cd "$ROOT"
"$BUILD/bench/sb_bench_contact" --csv bench/results/contact.csv --md bench/results/contact.md "$@"
