#!/bin/sh
# Renders docs/images/bouncing_ball.png: scenes/bouncing_ball.yaml's ball
# (read from scenes/sphere.itd) every 0.15 s of its first 1.5 s drawn
# together, as the Spring Systems tutorial shows "the union of the
# samples", each moved 0.42 m further along x than the one before so that
# time runs from left to right; the meshes are taken from the frames'
# POV-Ray export, the camera is set here. Run from the repository root
# after a build.
set -eu
out=$(mktemp -d)
./build/softbond run scenes/bouncing_ball.yaml --set output.formats=[pov] --set duration=1.5 --set frame_interval=0.15 \
    --output "$out" >/dev/null
{
    echo '#version 3.7;'
    echo 'global_settings { assumed_gamma 1.0 }'
    echo 'background { color rgb <1, 1, 1> }'
    echo 'camera { perspective location <2.1, 1.4, -4.6> look_at <2.1, 0.5, 0> angle 60 right x * 1000 / 360 }'
    echo 'light_source { <2, 5, -4> color rgb <1, 1, 1> }'
    echo 'light_source { <-2, 4, 2> color rgb <0.4, 0.4, 0.4> }'
    k=0
    for frame in "$out"/frame_*.pov; do
        sed -n '/^#declare softbond_mesh/,/^object {/p' "$frame" | sed "s/softbond_mesh/ball_$k/; /^object {/d"
        echo "object { ball_$k matrix <1, 0, 0,  0, 0, 1,  0, 1, 0,  0, 0, 0> translate <0.42 * $k, 0, 0>"
        echo '  texture { pigment { color rgb <0.9, 0.45, 0.15> } finish { ambient 0.25 diffuse 0.75 } } }'
        k=$((k + 1))
    done
    echo 'box { <-0.5, -0.02, -1>, <4.7, 0, 1> texture { pigment { checker color rgb <0.85, 0.85, 0.85> color rgb <0.7, 0.7, 0.7> scale 0.1 } finish { ambient 0.35 diffuse 0.65 } } }'
} >"$out/picture.pov"
docs/images/povray.sh "$out" bouncing_ball 1000 360
