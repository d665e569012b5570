#!/bin/sh
# Renders one frame of a scene to docs/images/NAME.png through the POV-Ray
# export and Debian's povray (docs/images/povray.sh). Run from the
# repository root after a build:
#
#   docs/images/render_frame.sh NAME SCENE TIME WIDTH HEIGHT [softbond run options...] <extra.pov
#
# The scene runs to TIME (duration and frame interval both set to it, so
# frame 1 is the state at TIME, or where a stop condition ended the run);
# the POV-Ray text on stdin is added to that frame, which holds the bodies
# only: the colliders, a floor. In it `to_pov` turns softbond's z-up
# coordinates into the frame's y-up ones.
set -eu
name=$1 scene=$2 time=$3 width=$4 height=$5
shift 5
out=$(mktemp -d)
./build/softbond run "$scene" --set output.formats=[pov] --set "duration=$time" --set "frame_interval=$time" \
    --output "$out" "$@" >/dev/null
frame=$(ls "$out"/frame_*.pov | tail -n 1)
{
    echo "#include \"$(basename "$frame")\""
    echo '#declare to_pov = transform { matrix <1, 0, 0,  0, 0, 1,  0, 1, 0,  0, 0, 0> }'
    cat
} >"$out/picture.pov"
docs/images/povray.sh "$out" "$name" "$width" "$height"
