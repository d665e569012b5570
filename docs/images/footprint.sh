#!/bin/sh
# Renders docs/images/footprint_none.png and footprint.png: a 5 mm probe
# (radius 2.5 mm) pressed 7.5 mm into a sheet of 5 mm spacing held along
# two sides, over a vertex, at t = 1.5 s, seen from the front a little
# below the sheet's plane (the underside's outline); first as a plain
# sphere (it holds one vertex down: a narrow cone), then with a footprint
# of 12.5 mm, 2.5 spacings (it presses the patch around the point of
# contact: a rounded dent). Run from the repository root after a build.
set -eu
render() { # NAME FOOTPRINT
    scene=$(mktemp --suffix=.yaml)
    cat >"$scene" <<YAML
mesh: {generator: sheet, nx: 21, ny: 21, width: 0.1, height: 0.1}
bond: {k: 200}
angle: {k: 0.0005}
density: 0.5
pin: left_edge
fixed: [20, 41, 62, 83, 104, 125, 146, 167, 188, 209, 230, 251, 272, 293, 314, 335, 356, 377, 398, 419, 440]
gravity: [0, 0, 0]
drag: 20
colliders:
  - type: sphere
    name: probe
    center: [0.05, 0.05, 0.0095]
    radius: 0.0025
    footprint: $2
    path: [{time: 0, translate: [0, 0, 0]}, {time: 1, translate: [0, 0, -0.0145]}]
contact: {thickness: 0.0005}
integrator: verlet
dt: 0.0001
YAML
    docs/images/render_frame.sh "$1" "$scene" 1.5 480 240 <<'POV'
camera { perspective location <0.05, -0.0035, -0.07> sky <0, 1, 0> right x * image_width / image_height angle 30
         look_at <0.05, -0.0035, 0.05> }
light_source { <-1, 2, -1> color rgb <0.6, 0.6, 0.6> }
light_source { <0.5, -2, -1> color rgb <0.8, 0.8, 0.8> }
POV
    rm -f "$scene"
}
render footprint_none 0
render footprint 0.0125
