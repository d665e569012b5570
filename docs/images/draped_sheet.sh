#!/bin/sh
# Renders docs/images/draped_sheet.png: scenes/draped_sheet.yaml's last frame
# (t = 2.5 s) exported as POV-Ray, with the ball and the floor of the
# scene's colliders added (the frame holds the cloth only), rendered by
# Debian's povray. Run from the repository root after a build.
set -eu
out=$(mktemp -d)
./build/softbond run scenes/draped_sheet.yaml --set output.formats=[pov] --set frame_interval=0.5 --output "$out"
cat >"$out/picture.pov" <<'POV'
#include "frame_000005.pov"
#declare to_pov = transform { matrix <1, 0, 0,  0, 0, 1,  0, 1, 0,  0, 0, 0> } // the frame's z up -> POV-Ray's y up
sphere { <0, 0, 0.3>, 0.3 transform { to_pov } texture { pigment { color rgb <0.55, 0.6, 0.7> } finish { ambient 0.3 diffuse 0.7 phong 0.3 } } }
box { <-1.2, -1.2, -0.02>, <1.2, 1.2, 0> transform { to_pov } texture { pigment { checker color rgb <0.85, 0.85, 0.85> color rgb <0.7, 0.7, 0.7> scale 0.2 } finish { ambient 0.35 diffuse 0.65 } } }
light_source { <-2, 4, 2> color rgb <0.5, 0.5, 0.5> }
POV
(cd "$out" && povray +Ipicture.pov +Opicture.png +W800 +H560 +A0.3 -D +FN >/dev/null 2>&1)
cp "$out/picture.png" docs/images/draped_sheet.png
rm -rf "$out"
echo "wrote docs/images/draped_sheet.png"
