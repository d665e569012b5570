#!/bin/sh
# Renders one frame of a scene to docs/images/NAME.png through the POV-Ray
# export and Debian's povray (ImageMagick is not needed: povray writes the
# PNG). Run from the repository root after a build:
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
(cd "$out" && povray +Ipicture.pov +Opicture.png +W"$width" +H"$height" +A0.3 -D +FN >/dev/null 2>&1)
cp "$out/picture.png" "docs/images/$name.png"
rm -rf "$out"
echo "wrote docs/images/$name.png"
