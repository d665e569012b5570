#!/bin/sh
# Makes the Viewer section's pictures, from the repository root after a
# build (needs xvfb-run, povray and ffmpeg), each with `softbond view
# --screenshot` under Xvfb or `softbond film`:
#   docs/images/viewer.png         scenes/falling_rock.yaml (the Spring Systems real-time
#                                  demo's rock) landed, at 0.7 s: edges off (F2), texture (F5);
#   docs/images/viewer_strain.png  scenes/draped_sheet.yaml at 1.2 s, edges coloured by
#                                  strain (F3);
#   docs/images/viewer_film.gif    `softbond film` of scenes/film_bounce.yaml (the film
#                                  maker's "Bounce", 0 to 1.5 s, 12 frames per second,
#                                  320 x 240) made a looping GIF by ffmpeg;
#   docs/images/film_draped_sheet.png  `softbond film` of scenes/draped_sheet.yaml, its
#                                  frame at 0.2 s (480 x 360): the sheet falling onto the ball.
set -eu
out=$(mktemp -d)
shot() { # SCENE SCRIPT PNG
    printf "$2" > "$out/script.txt"
    xvfb-run -a -s "-screen 0 1280x1024x24" ./build/softbond view "$1" --script "$out/script.txt" \
        --screenshot "$3" --size 960x720
}
shot scenes/falling_rock.yaml '0 key F2\n0 key F5\n0.7 quit\n' docs/images/viewer.png
shot scenes/draped_sheet.yaml '0 key F3\n1.2 quit\n' docs/images/viewer_strain.png
./build/softbond film scenes/film_bounce.yaml --set duration=1.5 --fps 12 --size 320x240 --output "$out/film"
ffmpeg -v error -y -i "$out/film/film_bounce.mp4" \
    -vf "split[a][b];[a]palettegen=max_colors=64[p];[b][p]paletteuse" -loop 0 docs/images/viewer_film.gif
./build/softbond film scenes/draped_sheet.yaml --set duration=0.2 --fps 5 --size 480x360 --output "$out/still"
cp "$out/still/frame_000001.png" docs/images/film_draped_sheet.png
rm -rf "$out"
echo "wrote docs/images/viewer.png, viewer_strain.png, viewer_film.gif and film_draped_sheet.png"
