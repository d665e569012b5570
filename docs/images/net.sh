#!/bin/sh
# Renders docs/images/net.png: scenes/net.yaml at the frame where the ball
# first touches the net (log.csv's first nonzero ball_fz), the tool up and
# the pulled knot down. The net has no faces, so its bonds are drawn here,
# a cylinder per row and column segment, from the frame's POV-Ray export;
# the ball is drawn where its free fall puts it (exact until that contact),
# the tool where its path holds it from 0.5 s to 1.5 s. Run from the
# repository root after a build.
set -eu
out=$(mktemp -d)
./build/softbond run scenes/net.yaml --set output.formats=[pov] --set duration=1.4 --output "$out" >/dev/null
time=$(awk -F, 'NR == 1 { for (c = 1; c <= NF; c++) if ($c == "ball_fz") col = c; next }
                $col != 0 { print $1; exit }' "$out/log.csv")
frame=$(awk -v t="$time" 'BEGIN { printf "frame_%06d.pov", t / 0.02 + 0.5 }')
awk -v t="$time" 'BEGIN { if (t < 0.5 || t > 1.5) { print "the ball arrives at " t " s, not while the tool is held"; exit 1 } }'
{
    sed -n '1,/^#declare softbond_mesh/p' "$out/$frame" | sed '$d'
    echo '#declare to_pov = transform { matrix <1, 0, 0,  0, 0, 1,  0, 1, 0,  0, 0, 0> }'
    echo '#declare cord = texture { pigment { color rgb <0.9, 0.45, 0.15> } finish { ambient 0.3 diffuse 0.7 } }'
    echo 'union {'
    sed -n '/vertex_vectors {/,/}/p' "$out/$frame" | sed '1,2d;$d' | tr -d '<>,' | awk -v n=21 '
        { x[NR - 1] = $1; y[NR - 1] = $2; z[NR - 1] = $3 }
        END {
            for (i = 0; i < NR; i++) {
                printf "sphere { <%s, %s, %s>, 0.007 }\n", x[i], y[i], z[i]
                if (i % n != n - 1) printf "cylinder { <%s, %s, %s>, <%s, %s, %s>, 0.004 }\n", x[i], y[i], z[i], x[i + 1], y[i + 1], z[i + 1]
                if (i + n < NR) printf "cylinder { <%s, %s, %s>, <%s, %s, %s>, 0.004 }\n", x[i], y[i], z[i], x[i + n], y[i + n], z[i + n]
            }
        }'
    echo 'texture { cord } transform { to_pov } }'
    awk -v t="$time" 'BEGIN { printf "sphere { <0.3, 0.6, %.6f>, 0.08 transform { to_pov } texture { pigment { color rgb <0.2, 0.4, 0.9> } finish { ambient 0.3 diffuse 0.7 phong 0.5 } } }\n", 3.2 - t - 0.5 * 9.81 * t * t }'
    echo '#declare steel = texture { pigment { color rgb <0.6, 0.62, 0.65> } finish { ambient 0.3 diffuse 0.6 phong 0.8 } }'
    echo 'sphere { <0.7, 0.55, 1.2>, 0.05 transform { to_pov } texture { steel } }'
    echo 'cylinder { <0.7, 0.55, 0.5>, <0.7, 0.55, 1.2>, 0.05 transform { to_pov } texture { steel } }'
    echo 'light_source { <-2, 4, 2> color rgb <0.5, 0.5, 0.5> }'
} >"$out/picture.pov"
docs/images/povray.sh "$out" net 560 440
echo "(the ball arrives at t = $time s)"
