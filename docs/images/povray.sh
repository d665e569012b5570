#!/bin/sh
# Renders DIR/picture.pov with Debian's povray into docs/images/NAME.png
# (povray writes the PNG itself: ImageMagick is not needed) and removes
# DIR. Used by the picture scripts beside it:
#
#   docs/images/povray.sh DIR NAME WIDTH HEIGHT
set -eu
dir=$1 name=$2 width=$3 height=$4
(cd "$dir" && povray +Ipicture.pov +Opicture.png +W"$width" +H"$height" +A0.3 -D +FN >/dev/null 2>&1)
cp "$dir/picture.png" "docs/images/$name.png"
rm -rf "$dir"
echo "wrote docs/images/$name.png"
