#!/bin/sh
# Renders docs/images/falling_rock.png: scenes/falling_rock.yaml at
# t = 0.4 s, the rock just landed on the floor. Run from the repository
# root after a build.
set -eu
docs/images/render_frame.sh falling_rock scenes/falling_rock.yaml 0.4 480 400 <<'POV'
box { <-1, -1, -0.02>, <1, 1, 0> transform { to_pov } texture { pigment { checker color rgb <0.85, 0.85, 0.85> color rgb <0.7, 0.7, 0.7> scale 0.1 } finish { ambient 0.35 diffuse 0.65 } } }
light_source { <-2, 4, 2> color rgb <0.5, 0.5, 0.5> }
POV
