#!/bin/sh
# Renders docs/images/cloth_on_rod_1.png and _4.png: scenes/cloth_on_rod.yaml
# at t = 0.5 s (the halves falling either side of the rod) and t = 2 s
# (piled on the floor), exported as POV-Ray, with the rod and the floor of
# the scene's colliders added (a frame holds the cloth only), rendered by
# Debian's povray. Run from the repository root after a build.
set -eu
out=$(mktemp -d)
./build/softbond run scenes/cloth_on_rod.yaml --set output.formats=[pov] --set frame_interval=0.5 --output "$out"
for frame in 1 4; do
    cat >"$out/picture_$frame.pov" <<POV
#include "frame_00000$frame.pov"
#declare to_pov = transform { matrix <1, 0, 0,  0, 0, 1,  0, 1, 0,  0, 0, 0> } // the frame's z up -> POV-Ray's y up
cylinder { <0, -0.8, 0.45>, <0, 0.8, 0.45>, 0.01 transform { to_pov } texture { pigment { color rgb <0.5, 0.45, 0.4> } finish { ambient 0.3 diffuse 0.7 phong 0.4 } } }
box { <-1.2, -1.2, -0.02>, <1.2, 1.2, 0> transform { to_pov } texture { pigment { checker color rgb <0.85, 0.85, 0.85> color rgb <0.7, 0.7, 0.7> scale 0.2 } finish { ambient 0.35 diffuse 0.65 } } }
light_source { <-2, 4, 2> color rgb <0.5, 0.5, 0.5> }
POV
    (cd "$out" && povray +Ipicture_$frame.pov +Opicture_$frame.png +W480 +H400 +A0.3 -D +FN >/dev/null 2>&1)
    cp "$out/picture_$frame.png" docs/images/cloth_on_rod_$frame.png
done
rm -rf "$out"
echo "wrote docs/images/cloth_on_rod_1.png and _4.png"
