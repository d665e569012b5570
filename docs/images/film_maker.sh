#!/bin/sh
# Renders docs/images/film_bounce.png, film_shapes.png and
# film_map_on_table.png: the film maker's scenes (scenes/film_*.yaml) at
# 0.44 s, 1.5 s and 0.12 s. Their frames hold every object, fixed ones too,
# in POV-Ray's own y-up frame. Run from the repository root after a build.
set -eu
for shot in "bounce 0.44" "shapes 1.5" "map_on_table 0.12"; do
    name=${shot% *}
    docs/images/render_frame.sh "film_$name" "scenes/film_$name.yaml" "${shot#* }" 480 400 <<'POV'
light_source { <-2, 4, -2> color rgb <0.5, 0.5, 0.5> }
POV
done
