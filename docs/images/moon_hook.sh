#!/bin/sh
# Renders docs/images/moon_hook.png: scenes/moon_hook.yaml at t = 2.2 s,
# the crescent hanging from the hook (drawn here as a rod from where the
# handle's path has its vertices) over the table. Run from the repository
# root after a build.
set -eu
docs/images/render_frame.sh moon_hook scenes/moon_hook.yaml 2.2 520 420 <<'POV'
cylinder { <0.29, 0.1, 0.366>, <0.29, 0.1, 0.6>, 0.004 transform { to_pov } texture { pigment { color rgb <0.4, 0.4, 0.45> } finish { ambient 0.3 diffuse 0.6 phong 0.6 } } }
box { <-0.6, -0.6, -0.01>, <0.8, 0.8, 0> transform { to_pov } texture { pigment { checker color rgb <0.85, 0.85, 0.85> color rgb <0.7, 0.7, 0.7> scale 0.1 } finish { ambient 0.35 diffuse 0.65 } } }
light_source { <-2, 4, 2> color rgb <0.5, 0.5, 0.5> }
POV
