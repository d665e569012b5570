#!/bin/sh
# Renders docs/images/cut_through.png: the hanging sheet of
# scenes/blade_cut.yaml cut through its triangles (cut_through: true) by a
# blade carried up it at 30 degrees to the mesh's columns, at t = 0.8 s,
# pinned along its top edge. The corner cut off hangs away along a
# straight incision, the blade's line, not the zigzag of the mesh's edges
# that severing bonds leaves. The step is half of blade_cut.yaml's: at
# 0.2 ms this slanted cut runs away at 0.55 s (docs/breakage.md, Cutting
# through triangles). Run from the repository root after a build.
set -eu
scene=$(mktemp --suffix=.yaml)
cat >"$scene" <<'YAML'
mesh: {generator: sheet, nx: 24, ny: 24, width: 0.3, height: 0.3, jitter: 0.2}
bond: {k: 400}
angle: {k: 0.01}
bend: {k: 0.0005}
density: 0.5
gravity: [0, -9.81, 0]
drag: 2.0
pin: top_edge
blades:
  - a: [0.11, -0.05, -0.02]
    b: [0.11, -0.05, 0.02]
    path:
      - {time: 0, translate: [0, 0, 0]}
      - {time: 0.8, translate: [0.2, 0.3464, 0]}
cut_through: true
kernels: reference
integrator: verlet
dt: 0.0001
YAML
docs/images/render_frame.sh cut_through "$scene" 0.8 480 400 <<'POV'
light_source { <-2, 4, 2> color rgb <0.5, 0.5, 0.5> }
POV
rm -f "$scene"
