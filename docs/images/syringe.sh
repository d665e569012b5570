#!/bin/sh
# Renders docs/images/syringe.png: scenes/syringe.yaml at t = 1.8 s, the
# needle (the capsule collider, drawn here where its path has it) held
# 3.1 cm into the body on the table. Run from the repository root after a
# build.
set -eu
docs/images/render_frame.sh syringe scenes/syringe.yaml 1.8 480 400 <<'POV'
#declare needle = texture { pigment { color rgb <0.75, 0.78, 0.8> } finish { ambient 0.3 diffuse 0.6 phong 0.8 } }
sphere { <0.00023, -0.00056, 0.08045>, 0.002 transform { to_pov } texture { needle } }
cylinder { <0.00023, -0.00056, 0.08045>, <0.00023, -0.00056, 0.16045>, 0.002 transform { to_pov } texture { needle } }
box { <-0.3, -0.3, -0.01>, <0.3, 0.3, 0> transform { to_pov } texture { pigment { checker color rgb <0.85, 0.85, 0.85> color rgb <0.7, 0.7, 0.7> scale 0.05 } finish { ambient 0.35 diffuse 0.65 } } }
light_source { <-2, 4, 2> color rgb <0.5, 0.5, 0.5> }
POV
