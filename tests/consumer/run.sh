#!/bin/sh
# Usage: run.sh BUILD_DIR CONSUMER_SOURCE WORK_DIR
set -eu
build=$1 src=$2 work=$3
rm -rf "$work"
cmake --install "$build" --prefix "$work/prefix" >/dev/null
prefix="$work/prefix"
libdir=$(ls -d "$prefix"/lib*/ | head -n 1)

cmake -S "$src" -B "$work/cmake-build" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$work/cmake-build" >/dev/null
LD_LIBRARY_PATH="$libdir" "$work/cmake-build/consumer"

PKG_CONFIG_PATH=$(find "$prefix" -name softbond.pc -exec dirname {} \;)
export PKG_CONFIG_PATH
cc -std=c11 -o "$work/consumer-pc" "$src/main.c" $(pkg-config --cflags --libs softbond) -lm
LD_LIBRARY_PATH="$libdir" "$work/consumer-pc"
