#!/bin/sh
# Renders docs/images/tearing_sheet.png and blade_cut.png: the last frame
# (t = 1 s) of scenes/tearing_sheet.yaml, the sheet torn through by its two
# handles, and scenes/blade_cut.yaml at t = 0.7 s, the hanging sheet cut up
# its middle through its triangles, the straight incision gaping as the
# blade reaches the top edge. Each picture has its own camera on the sheet
# (the frame's own frames every vertex). Run from the repository root after
# a build.
set -eu
docs/images/render_frame.sh tearing_sheet scenes/tearing_sheet.yaml 1 480 400 <<'POV'
camera { perspective location <0.15, 0.85, -0.02> sky <0, 0, 1> right x * image_width / image_height angle 45
         look_at <0.15, 0, 0.13> }
light_source { <0.15, 2, 0.15> color rgb <0.6, 0.6, 0.6> }
POV
docs/images/render_frame.sh blade_cut scenes/blade_cut.yaml 0.7 480 400 <<'POV'
light_source { <-2, 4, 2> color rgb <0.5, 0.5, 0.5> }
POV
