#!/bin/sh
# The package after an install, both ways: `cmake --install` into a scratch
# prefix, then `import softbond` from it; and `pip install` (offline, against
# that prefix through pkg-config) of a copy of python/ into a scratch target.
# usage: install.sh BUILD_DIR SOURCE_DIR WORK_DIR PYTHON
set -eu
build=$1 source=$2 work=$3 python=$4
rm -rf "$work"
mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
site=$(find "$work/prefix" -type d -name dist-packages | head -n 1)
cd "$work"
PYTHONPATH="$site" "$python" -c 'import softbond; s = softbond.Solver(softbond.Model.sheet(nx=3, ny=3), threads=1); s.advance(1e-3); print("cmake --install:", softbond.__file__)'
cp -r "$source/python" "$work/python"
rm -rf "$work/python/build" "$work/python/softbond.egg-info"
PKG_CONFIG_PATH="$work/prefix/lib/pkgconfig" "$python" -m pip install --quiet --no-build-isolation --no-index --no-deps \
    --target "$work/target" "$work/python" > "$work/pip.log" 2>&1 || { cat "$work/pip.log"; exit 1; }
PYTHONPATH="$work/target" "$python" -c 'import softbond; s = softbond.Solver(softbond.Model.sheet(nx=3, ny=3), threads=1); s.advance(1e-3); print("pip install:", softbond.__file__)'
