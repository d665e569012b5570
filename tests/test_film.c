/* `softbond film` (cli/film.c): the default scene for 0.3 s at 30 frames
 * per second and 64 x 48 pixels makes an MP4 whose video stream ffprobe
 * counts 10 frames in, and no two consecutive decoded frames are the same
 * (ffmpeg's framemd5 of each). A missing povray, or an --eye that is not
 * x,y,z, is said in one line, exit 2. A movie that cannot be written
 * (--movie /dev/full) is one line naming it and exit 1; the frames'
 * pictures are whole PNGs and no NAME.tmp is left. The film of
 * scenes/draped_sheet.yaml shows its ball: the colliders' teal where the
 * ball is, none in the same film without the ball; its progress bar (on a
 * terminal, script(1)) ends at 100 %. A kinematic collider moves from
 * frame to frame; a .pov scene is filmed. */
#define _POSIX_C_SOURCE 200809L
#include "test_util.h"

#include <stb/stb_image.h>
#include <stdio.h>

#define DIR "test_film_out"

/* The lines a command prints, joined, or fails. */
static void output_of(const char* command, char* out, size_t size) {
    FILE* p = popen(command, "r");
    assert_non_null(p);
    size_t n = fread(out, 1, size - 1, p);
    out[n] = '\0';
    assert_int_equal(pclose(p), 0);
}

static void test_ten_frames_that_differ(void** state) {
    (void)state;
    char command[1024], text[8192];
    snprintf(command, sizeof command,
             "rm -rf " DIR " && %s film %s/scenes/default.yaml --set duration=0.3 --fps 30 --size 64x48 --output " DIR
             " >/dev/null",
             SB_PROGRAM, SB_SOURCE_DIR);
    assert_int_equal(system(command), 0);
    output_of("ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames,width,height "
              "-of csv=p=0 " DIR "/default.mp4",
              text, sizeof text);
    printf("ffprobe: %s", text);
    assert_string_equal(text, "64,48,10\n");
    output_of("ffmpeg -v error -i " DIR "/default.mp4 -f framemd5 - | grep -v '^#' | awk -F, '{print $6}'", text,
              sizeof text);
    char* hashes[16];
    int n = 0;
    for (char* line = strtok(text, "\n"); line && n < 16; line = strtok(NULL, "\n")) hashes[n++] = line;
    assert_int_equal(n, 10);
    for (int k = 1; k < n; k++)
        if (strcmp(hashes[k], hashes[k - 1]) == 0) fail_msg("frames %d and %d are the same", k - 1, k);
}

static void test_missing_povray_is_said(void** state) {
    (void)state;
    char command[1024], text[1024];
    snprintf(command, sizeof command,
             "PATH=/nonexistent %s film %s/scenes/default.yaml --output " DIR "_missing 2>&1; echo exit $?", SB_PROGRAM,
             SB_SOURCE_DIR);
    output_of(command, text, sizeof text);
    assert_string_equal(text, "softbond: film: povray is not on PATH (install Debian's povray: apt-get install "
                              "povray)\nexit 2\n");
}

static void test_bad_camera_is_refused(void** state) {
    (void)state;
    char command[1024], text[1024];
    snprintf(command, sizeof command,
             "%s film %s/scenes/default.yaml --eye 1,2 --output " DIR "_bad 2>&1; echo exit $?", SB_PROGRAM,
             SB_SOURCE_DIR);
    output_of(command, text, sizeof text);
    assert_string_equal(text, "softbond: --eye: expected x,y,z in metres, got '1,2'\nexit 2\n");
}

static void test_movie_onto_a_full_device_fails(void** state) {
    (void)state;
    char command[1024], text[1024];
    snprintf(command, sizeof command,
             "rm -rf " DIR "_full && %s film %s/scenes/default.yaml --set duration=0.1 --size 32x24 --output " DIR
             "_full --movie /dev/full 2>&1; echo exit $?",
             SB_PROGRAM, SB_SOURCE_DIR);
    output_of(command, text, sizeof text);
    assert_string_equal(text, "softbond: film: ffmpeg could not make /dev/full\nexit 1\n");
    output_of("ls " DIR "_full | tr '\\n' ' '", text, sizeof text);
    assert_string_equal(text, "film_setting.inc frame_000000.png frame_000000.pov frame_000001.png frame_000001.pov frame_000002.png "
                              "frame_000002.pov frame_000003.png frame_000003.pov ");
    int w, h, channels;
    unsigned char* rgb = stbi_load(DIR "_full/frame_000003.png", &w, &h, &channels, 3);
    assert_non_null(rgb); /* a whole PNG */
    assert_true(w == 32 && h == 24);
    stbi_image_free(rgb);
}

/* Pixels of the colliders' teal (green above red and blue) in a PNG. */
static int teal_pixels(const char* path, int* width, int* height) {
    int channels;
    unsigned char* rgb = stbi_load(path, width, height, &channels, 3);
    if (!rgb) fail_msg("cannot read %s", path);
    int count = 0;
    for (int i = 0; i < *width * *height; i++) {
        const unsigned char* c = rgb + 3 * i;
        count += c[1] > c[0] + 30 && c[1] > c[2] + 8;
    }
    stbi_image_free(rgb);
    return count;
}

static void test_film_shows_the_colliders(void** state) {
    (void)state;
    char command[2048], text[65536];
    snprintf(command, sizeof command,
             "rm -rf " DIR "_ball && script -qec '%s film %s/scenes/draped_sheet.yaml --set duration=0.1 --size 96x72 "
             "--output " DIR "_ball' /dev/null",
             SB_PROGRAM, SB_SOURCE_DIR);
    output_of(command, text, sizeof text);
    /* the bar's last drawing is 100 % */
    char *bar = strstr(text, "softbond: film ["), *last = NULL;
    for (; bar; bar = strstr(bar + 1, "softbond: film [")) last = bar;
    assert_non_null(last);
    assert_non_null(strstr(last, "softbond: 4 frames"));
    char* done = strstr(last, "] 100%  done");
    if (!done || done > strchr(last, '\n')) fail_msg("the progress bar ends: %.80s", last);
    int w, h;
    int ball = teal_pixels(DIR "_ball/frame_000000.png", &w, &h);
    printf("teal pixels with the ball: %d of %d\n", ball, w * h);
    assert_int_equal(w, 96);
    TU_ASSERT_LE(w * h / 50, ball); /* the ball below the sheet: more than 2 % of the picture (3.6 %) */
    snprintf(command, sizeof command,
             "rm -rf " DIR "_noball && %s film %s/scenes/draped_sheet.yaml --set duration=0.1 --size 96x72 --set "
             "'colliders=[{type: plane}]' --output " DIR "_noball >/dev/null",
             SB_PROGRAM, SB_SOURCE_DIR);
    assert_int_equal(system(command), 0);
    assert_int_equal(teal_pixels(DIR "_noball/frame_000000.png", &w, &h), 0);
}

/* A kinematic collider moves in the film: scenes/kinematic_sphere.yaml's
 * pusher, still at 0.25 s, is 0.6 m on (its path) at 1.5 s. */
static void test_film_moves_the_colliders(void** state) {
    (void)state;
    char command[1024], text[4096];
    snprintf(command, sizeof command,
             "rm -rf " DIR "_kin && %s film %s/scenes/kinematic_sphere.yaml --set duration=1.5 --fps 4 --size 32x24 "
             "--output " DIR "_kin >/dev/null && grep -h '^sphere' " DIR "_kin/frame_000001.pov " DIR
             "_kin/frame_000006.pov",
             SB_PROGRAM, SB_SOURCE_DIR);
    output_of(command, text, sizeof text);
    printf("%s", text);
    double x[2][3];
    assert_int_equal(sscanf(text, "sphere { <%lf, %lf, %lf>, 0.15 texture { softbond_collider } }\n"
                                  "sphere { <%lf, %lf, %lf>",
                            &x[0][0], &x[0][1], &x[0][2], &x[1][0], &x[1][1], &x[1][2]),
                     6);
    /* POV-Ray's axes: the scene's up (+y, against gravity) is POV's +y, the scene's z POV's z */
    TU_ASSERT_NEAR(x[0][2], -0.3, 1e-9);
    TU_ASSERT_NEAR(x[1][2], 0.3, 1e-9);
    TU_ASSERT_NEAR(x[1][0], x[0][0], 1e-9);
}

/* A POV-Ray scene of mesh2 objects is a scene itself (the film maker's input). */
static void test_film_of_a_pov_scene(void** state) {
    (void)state;
    char command[1024], text[4096];
    snprintf(command, sizeof command,
             "rm -rf " DIR "_pov && %s film %s/scenes/film_bounce.pov --set duration=0.04 --fps 25 --size 32x24 "
             "--output " DIR "_pov 2>&1; echo exit $?",
             SB_PROGRAM, SB_SOURCE_DIR);
    output_of(command, text, sizeof text);
    TU_ASSERT_CONTAINS(text, "softbond: 2 frames (32x24, 25 per second) in " DIR "_pov, movie " DIR
                             "_pov/film_bounce.mp4\nexit 0\n");
    output_of("head -c 2000 " DIR "_pov/frame_000001.pov", text, sizeof text);
    TU_ASSERT_CONTAINS(text, "#include \"film_setting.inc\"");
    TU_ASSERT_CONTAINS(text, "mesh2 {");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ten_frames_that_differ),
        cmocka_unit_test(test_missing_povray_is_said),
        cmocka_unit_test(test_bad_camera_is_refused),
        cmocka_unit_test(test_movie_onto_a_full_device_fails),
        cmocka_unit_test(test_film_shows_the_colliders),
        cmocka_unit_test(test_film_of_a_pov_scene),
        cmocka_unit_test(test_film_moves_the_colliders),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
