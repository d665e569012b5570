#!/bin/sh
# The layers run one way (DESIGN.md): common <- mesh <- kernels <- haptics,
# mesh/io on top of mesh, scenes (the program) on top of all, the viewer
# (viewer/: view and film) on top of scenes. Fails on any
# #include "DIR/..." that reaches a layer above the file's own.
set -eu
cd "$1"
status=0
check() { # check DIR-GLOB FORBIDDEN-REGEX
    dir=$1 forbidden=$2
    hits=$(grep -nE "#include \"($forbidden)/" $dir 2>/dev/null || true)
    if [ -n "$hits" ]; then
        echo "layer violation in $dir (may not include $forbidden):" >&2
        echo "$hits" >&2
        status=1
    fi
}
check "common/*.c common/*.h" "mesh|kernels|haptics|scenes|bench"
check "mesh/*.c mesh/*.h" "mesh/io|kernels|haptics|scenes|bench"
check "mesh/io/*.c mesh/io/*.h" "kernels|haptics|scenes|bench"
check "kernels/*/*.c kernels/*/*.h kernels/contact/colliders/*.c kernels/contact/colliders/*.h" "mesh/io|haptics|scenes|bench"
check "haptics/*.c haptics/*.h" "mesh/io|scenes|bench"
check "include/softbond/*.h" "common|mesh|kernels|haptics|scenes|viewer|bench"
check "scenes/*.c scenes/*.h" "viewer|bench"
[ $status -eq 0 ] && echo "layers: one way"
exit $status
