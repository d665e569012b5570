#!/bin/sh
# Renders docs/images/cloth_fixed_points_2.png and _4.png:
# scenes/cloth_fixed_points.yaml at t = 3 s held by two corners and by all
# four. Run from the repository root after a build.
set -eu
for held in "2 [870, 899]" "4 [0, 29, 870, 899]"; do
    docs/images/render_frame.sh "cloth_fixed_points_${held%% *}" scenes/cloth_fixed_points.yaml 3 480 400 \
        --set "fixed=${held#* }" <<'POV'
light_source { <-2, 4, 2> color rgb <0.5, 0.5, 0.5> }
POV
done
