#!/bin/sh
# Usage: run.sh BUILD_DIR CONSUMER_SOURCE WORK_DIR
# Installs softbond into a scratch prefix; checks that the shared libraries
# export exactly the public API (every SB_API function of the installed
# headers, nothing else); builds three programs against the installation,
# through find_package(softbond) and through pkg-config, and runs them.
set -eu
build=$1 src=$2 work=$3
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" >/dev/null
prefix="$work/prefix"
libdir=$(ls -d "$prefix"/lib*/ | head -n 1)

# The public API: the names declared SB_API in the installed headers.
grep -h '^SB_API ' "$prefix"/include/softbond/*.h |
    sed -E 's/^.*[ *](sb_[a-z0-9_]+)\(.*$/\1/' | sort -u >"$work/api.txt"
nm -D --defined-only "$libdir/libsoftbond.so" "$libdir/libsoftbond_io.so" "$libdir/libsoftbond_scene.so" |
    awk '$2 == "T" {print $3}' | sort -u >"$work/exported.txt"
if ! cmp -s "$work/api.txt" "$work/exported.txt"; then
    echo "exported symbols differ from the public API (< public only, > exported only):" >&2
    diff "$work/api.txt" "$work/exported.txt" >&2 || true
    exit 1
fi
# The solver library needs neither importer.
if ldd "$libdir/libsoftbond.so" | grep -E 'assimp|meshoptimizer' >&2; then
    echo "libsoftbond.so links a mesh importer" >&2
    exit 1
fi
echo "exports: $(wc -l <"$work/api.txt") public functions, nothing else"
# The scene library reaches the others through their public API only: an
# internal function would be hidden there and fail to resolve at run time.
nm -D --undefined-only "$libdir/libsoftbond_scene.so" | awk '$2 ~ /^sb_/ {print $2}' | sort -u >"$work/scene_uses.txt"
if [ -n "$(comm -23 "$work/scene_uses.txt" "$work/exported.txt")" ]; then
    echo "libsoftbond_scene.so uses functions the other libraries do not export:" >&2
    comm -23 "$work/scene_uses.txt" "$work/exported.txt" >&2
    exit 1
fi

printf 'v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n' >"$work/square.obj"
printf 'mesh: {generator: sheet, nx: 5, ny: 4}\npin: top_corners\ndt: 0.001\nthreads: 1\n' >"$work/sheet.yaml"
cmake -S "$src" -B "$work/cmake-build" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$work/cmake-build" >/dev/null
LD_LIBRARY_PATH="$libdir" "$work/cmake-build/consumer"
LD_LIBRARY_PATH="$libdir" "$work/cmake-build/consumer_io" "$work/square.obj"
LD_LIBRARY_PATH="$libdir" "$work/cmake-build/consumer_scene" "$work/sheet.yaml"

PKG_CONFIG_PATH=$(find "$prefix" -name softbond.pc -exec dirname {} \;)
export PKG_CONFIG_PATH
cc -std=c11 -o "$work/consumer-pc" "$src/main.c" $(pkg-config --cflags --libs softbond) -lm
LD_LIBRARY_PATH="$libdir" "$work/consumer-pc"
cc -std=c11 -o "$work/consumer-io-pc" "$src/main_io.c" $(pkg-config --cflags --libs softbond_io)
LD_LIBRARY_PATH="$libdir" "$work/consumer-io-pc" "$work/square.obj"
cc -std=c11 -o "$work/consumer-scene-pc" "$src/main_scene.c" $(pkg-config --cflags --libs softbond_scene)
LD_LIBRARY_PATH="$libdir" "$work/consumer-scene-pc" "$work/sheet.yaml"

# Installed for use: the scenes, the manual, the examples, the man page and
# the bash completion, in their usual places; the installed program runs an
# installed scene, and the installed examples build against the installation.
share="$prefix/share"
for file in softbond/scenes/default.yaml softbond/scenes/bowl.obj softbond/scenes/haptics_probe.csv \
    doc/softbond/README.md doc/softbond/LICENSE doc/softbond/CHANGELOG.md doc/softbond/docs/scene_keys.md \
    doc/softbond/docs/getting_started.md doc/softbond/examples/hello.c doc/softbond/examples/CMakeLists.txt \
    man/man1/softbond.1 bash-completion/completions/softbond; do
    [ -f "$share/$file" ] || { echo "not installed: share/$file" >&2; exit 1; }
done
LD_LIBRARY_PATH="$libdir" "$prefix/bin/softbond" run "$share/softbond/scenes/default.yaml" \
    --set duration=0.01 --set threads=1 --output "$work/installed-run" >/dev/null
[ -f "$work/installed-run/log.csv" ] || { echo "the installed program wrote no log.csv" >&2; exit 1; }
cmake -S "$share/doc/softbond/examples" -B "$work/examples-build" -DCMAKE_PREFIX_PATH="$prefix" >/dev/null
cmake --build "$work/examples-build" >/dev/null
LD_LIBRARY_PATH="$libdir" "$work/examples-build/example_hello" | grep -q "the free corner at z = -"
echo "installed: scenes, manual, examples (built and run), man page, bash completion"
