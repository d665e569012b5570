#!/bin/sh
# Makes the gallery (docs/gallery.md and its thumbnails here) from the
# repository root after a build; needs xvfb-run (Mesa's software OpenGL).
# For each committed scene: a 320 x 240 still from `softbond view` (edges
# and statistics off) at the
# time below (half its duration, at most 2 s), and the wall time of
# `softbond run` on 2 threads without frames (output.frames=false) on this
# machine. Usage: sh docs/images/gallery/make.sh [SCENE.yaml...]
set -eu
here=docs/images/gallery
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
what() { # one line on what each scene shows
    case $1 in
    ball_net) echo "a ball thrown into a net held at its edges: the net catches it and throws it back (dynamic collider)" ;;
    blade_cut) echo "a sheet hanging from its top corners cut through up its middle by a moving blade: a straight incision that gapes" ;;
    bouncing_ball) echo "a soft icosphere dropped onto a floor, bouncing (Spring Systems tutorial)" ;;
    box_table) echo "a tablecloth dropped onto a turned box: it settles on the top and hangs over the edges" ;;
    capsule_hook) echo "a cloth dropped across a capsule rail folds over it like a towel on a hook" ;;
    cloth_fixed_points) echo "a cloth held at fixed points (the Spring Systems film maker's sub-version)" ;;
    cloth_on_rod) echo "a cloth dropped across a thin rod: its halves swing together and pile on the floor (self-contact)" ;;
    corotated_body) echo "a block of liver-like tissue (E 3.5 kPa, ν 0.45) settling on a table: co-rotated finite elements" ;;
    default) echo "a sheet held at its two top corners falls and swings to rest (what make demo runs)" ;;
    draped_sheet) echo "a sheet drapes over a ball on the floor, its corners folding down" ;;
    falling_rock) echo "a rock read from a 3DS file falls onto a surface (Spring Systems real-time demo)" ;;
    film_bounce) echo "the film maker's Bounce: a soft ball dropped onto a floor" ;;
    film_map_on_table) echo "the film maker's Map on table: a map dropped onto a table" ;;
    film_shapes) echo "the film maker's Shapes: a block, a ball and a cube fall onto a floor and each other" ;;
    haptics_probe) echo "a sphere driven by a scripted haptic device presses into a sheet held on two sides" ;;
    hook_pull) echo "a sheet pinned along its left edge is pulled by a hook (a handle on a path)" ;;
    kinematic_sphere) echo "a curtain pushed aside by a ball moving on a keyframed path" ;;
    mesh_bowl) echo "a cloth dropped into a bowl that is a triangle-mesh collider" ;;
    moon_hook) echo "a crescent moon pulled by a hook (Sekercioglu and Duysak, Figure 5a)" ;;
    net) echo "a net hit by a ball and a tool while pulled down from one side (Figure 5b)" ;;
    sudhamani_sheet) echo "a tissue sheet clamped on the left, pushed at its middle by a constant force" ;;
    syringe) echo "a needle, a kinematic capsule, pushed into a soft body (Figure 4)" ;;
    tearing_sheet) echo "a sheet torn apart by two hard handles: bonds break past 25 % strain" ;;
    *) echo "(no description)" ;;
    esac
}
[ $# -gt 0 ] || set -- scenes/*.yaml
rows=$out/rows.md
: > "$rows"
for scene in "$@"; do
    name=$(basename "$scene" .yaml)
    integrator=$(sed -n 's/^integrator: *\([a-z_]*\).*/\1/p' "$scene")
    duration=$(sed -n 's/^duration: *\([0-9.e+-]*\).*/\1/p' "$scene")
    t=$(awk -v d="$duration" 'BEGIN {t = d / 2; if (t > 2) t = 2; print t}')
    printf "%s key F2\n%s key o\n%s quit\n" 0 0 "$t" > "$out/script.txt"
    xvfb-run -a -s "-screen 0 640x480x24" ./build/softbond view "$scene" --size 320x240 \
        --script "$out/script.txt" --screenshot "$here/$name.png" > /dev/null
    start=$(date +%s.%N)
    ./build/softbond run "$scene" --threads 2 --set output.frames=false --output "$out/run" > /dev/null
    end=$(date +%s.%N)
    wall=$(awk -v a="$start" -v b="$end" 'BEGIN {printf "%.1f", b - a}')
    printf '| [![%s](images/gallery/%s.png)](../scenes/%s.yaml) | [`%s`](../scenes/%s.yaml): %s | %s | %s s | %s s |\n' \
        "$name" "$name" "$name" "$name" "$name" "$(what "$name")" "${integrator:-verlet}" "$duration" "$wall" >> "$rows"
    echo "$name: $wall s" >&2
done
{
    cat <<'HEAD'
# Gallery

<!-- Made by docs/images/gallery/make.sh: edit the descriptions there. -->

Every committed scene in `scenes/`, as `softbond view SCENE` shows it at
half its duration (at most 2 s), edges off (F2) and statistics hidden (o):
click a picture for the
scene file. Run any of them with `softbond run scenes/NAME.yaml` or watch it
with `softbond view scenes/NAME.yaml`. *Run time* is the wall time of
`softbond run` on 2 threads without writing frames, on the project's 2-core
machine (shared, so a rough guide).

| scene | what it shows | integrator | simulated | run time |
|---|---|---|---|---|
HEAD
    cat "$rows"
} > docs/gallery.md
echo "wrote docs/gallery.md and $(wc -l < "$rows") pictures in $here" >&2
