#!/bin/sh
# Renders docs/images/face_contact.png: a coarse sheet (6 cm between
# vertices) dropped on a sphere of 1 cm radius that sits under the middle
# of a cell, at t = 0.15 s. The sphere is smaller than the spacing: face
# contact stops the triangle it meets, so the sheet tents over it instead of
# falling through between the vertices. Run from the repository root after
# a build.
set -eu
scene=$(mktemp --suffix=.yaml)
cat >"$scene" <<'YAML'
mesh: {generator: sheet, nx: 6, ny: 6, width: 0.3, height: 0.3, translate: [-0.15, -0.15, 0.05]}
bond: {k: 200}
angle: {k: 0.02}
bend: {k: 0.0005}
density: 0.2
drag: 2.0
colliders:
  - {type: sphere, name: probe, center: [0, 0, 0.03], radius: 0.01, friction: 0.8}
integrator: verlet
dt: 0.0002
YAML
docs/images/render_frame.sh face_contact "$scene" 0.15 480 360 <<'POV'
camera { perspective location <0.3, -0.3, -0.4> sky <0, 1, 0> right x * image_width / image_height angle 28
         look_at <0, -0.02, 0> }
sphere { <0, 0, 0.03>, 0.01 transform { to_pov } texture { pigment { color rgb <0.8, 0.3, 0.25> } finish { ambient 0.3 diffuse 0.7 phong 0.5 } } }
light_source { <-1, 2, -1> color rgb <0.6, 0.6, 0.6> }
light_source { <0.5, -2, -1> color rgb <0.8, 0.8, 0.8> }
POV
rm -f "$scene"
