#!/bin/sh
# Usage: layers.sh SOURCE_DIR BUILD_DIR
#
# The layers run one way (DESIGN.md, "Layers"): a file may use what its own
# layer and the layers below it define, never what a layer above does. Two
# checks, each printing every violation on a line of its own:
#   - the #include "DIR/..." lines of the sources:
#       FILE includes HEADER (layer X above Y)
#   - the calls: each object file's undefined symbols (nm) against the
#     symbols the object files of the other layers define, the objects
#     being BUILD_DIR/CMakeFiles/*.dir/<source path>.o:
#       FILE uses SYMBOL from FILE2 (layer X above Y)
# and the public headers (include/softbond/) include only each other.

# The layers, lowest first. A directory belongs to the longest layer that
# is a prefix of it (mesh/io is not mesh; haptics/tools is haptics).
LAYERS="common mesh kernels haptics mesh/io scenes viewer cli bench tests"
# The kernels' rooms, lowest first (DESIGN.md, "The map"): each is a layer
# of its own, in place of kernels in LAYERS.
KERNEL_ROOMS="kernels/runtime kernels/forces kernels/linear kernels/state kernels/contact kernels/interaction
              kernels/integrators kernels/solver"

set -eu
if [ $# -ne 2 ]; then
    echo "usage: layers.sh SOURCE_DIR BUILD_DIR" >&2
    exit 2
fi
src=$1 build=$(cd "$2" && pwd)
cd "$src"
order=$(echo " $LAYERS " | sed "s| kernels | $(echo $KERNEL_ROOMS) |")
order=$(echo $order)

# One record a line: "INC file header", "DEF file symbol", "USE file symbol".
records() {
    find common mesh kernels haptics scenes viewer cli bench tests -name '*.[ch]' -exec grep -H '^[[:space:]]*#[[:space:]]*include[[:space:]]*"' {} + |
        sed -E 's/^([^:]*):[^"]*"([^"]*)".*$/INC \1 \2/'
    find "$build/CMakeFiles" -path '*.dir/*' -name '*.o' | sort | while read -r object; do
        file=${object#"$build/CMakeFiles/"*.dir/}
        file=${file%.o}
        [ -f "$file" ] || continue # a stale object of a file since moved or removed
        echo "OBJ $file -"
        nm --defined-only -g "$object" | awk -v f="$file" 'NF == 3 {print "DEF", f, $3}'
        nm --undefined-only -g "$object" | awk -v f="$file" '{print "USE", f, $NF}'
    done
}

violations=$(records | awk -v order="$order" '
    BEGIN { n = split(order, L, " ") }
    # the index of the longest layer that is a prefix of path p; 0 = none
    function layer(p,   i, best, length_best) {
        best = 0; length_best = 0
        for (i = 1; i <= n; i++)
            if ((p == L[i] || index(p, L[i] "/") == 1) && length(L[i]) > length_best) {
                best = i; length_best = length(L[i])
            }
        return best
    }
    $1 == "INC" {
        includes++
        from = layer($2); to = layer($3)
        if (from && to > from) printf "%s includes %s (layer %s above %s)\n", $2, $3, L[to], L[from]
    }
    $1 == "OBJ" { objects++ }
    # a symbol defined in several layers counts as the lowest of them
    $1 == "DEF" {
        at = layer($2)
        if (!($3 in defined) || at < defined[$3]) { defined[$3] = at; definer[$3] = $2 }
    }
    $1 == "USE" { user[uses] = $2; used[uses] = $3; uses++ }
    END {
        for (i = 0; i < uses; i++) {
            from = layer(user[i]); s = used[i]
            if (from && (s in defined) && defined[s] > from)
                printf "%s uses %s from %s (layer %s above %s)\n", user[i], s, definer[s], L[defined[s]], L[from]
        }
        if (!objects) print "no object files under BUILD_DIR/CMakeFiles: build first"
        printf "checked: %d includes, %d object files, %d symbol uses\n", includes, objects, uses > "/dev/stderr"
    }' | sort)

# The public headers include nothing of the sources.
public=$(grep -nE '#include "' include/softbond/*.h | grep -v '#include "softbond/' || true)
[ -n "$public" ] && violations="$violations${violations:+
}$(echo "$public" | sed 's/$/ (a public header includes a source header)/')"

if [ -n "$violations" ]; then
    echo "layer violations (layers, lowest first: $order):" >&2
    echo "$violations" >&2
    exit 1
fi
echo "layers: one way ($order)"
