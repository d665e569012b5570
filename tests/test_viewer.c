/* The viewer (viewer/view.h), run in this process under Xvfb with Mesa's
 * software OpenGL (ctest starts it through xvfb-run). Each case runs the
 * default scene (the 30 x 30 sheet held at its top corners) with a script
 * and checks the picture (PNG) or the last snapshot drawn:
 *   - paused at rest: the screenshot is not blank, and the box of the
 *     pixels that are not background matches the sheet's corners projected
 *     here (a pinhole camera written in this file) within a few pixels;
 *   - F2 off: far fewer dark (edge) pixels on the sheet;
 *   - F3: the strain colour scale (red and blue) appears at the right edge;
 *   - h: the list of keys on a white card;
 *   - g: gravity off from the start, every published vertical velocity is 0;
 *   - r: gravity reversed, the sheet rises;
 *   - a scripted drag of the middle vertex pulls it toward the cursor;
 *   - with the "mouse" haptic device, a drag moves the probe into the sheet;
 *   - a bad script line is refused naming file:line;
 *   - without a display, one line and exit 2;
 *   - a solver failure: on stderr, exit 3, in red wrapped in the window;
 *   - a screenshot that cannot be written (/dev/full): one line naming the
 *     file, exit 1, and no PNG left under a regular file's name;
 *   - a script replays identically: twice the same paused time, step,
 *     positions and picture (p's screenshot, the scene below the overlay);
 *   - n: three single steps from the start are three steps;
 *   - l: a reload starts the scene anew (time 0, still paused);
 *   - a net (factory: net) is drawn as edges: F2 off leaves nearly nothing;
 *     the camera at the start frames the net's ball too, high above it. */
#define _POSIX_C_SOURCE 200809L
#include "test_util.h"

#include "viewer/view.h"
#include "viewer/input_script.h"

#include <stb/stb_image.h>
#include <stdio.h>
#include <unistd.h>

#define SCENE SB_SOURCE_DIR "/scenes/default.yaml"
enum { W = 480, H = 360 };
static const unsigned char BACKGROUND[3] = {219, 227, 237}; /* the clear colour 0.86, 0.89, 0.93 */

typedef struct picture {
    unsigned char* rgb;
    int width, height;
} picture;

static void write_script(const char* path, const char* text) {
    FILE* f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

/* Runs the viewer on a scene with one --set (or none) and the script (for
 * at most `frames` frames; 0: until the script quits); the screenshot is
 * read back when png is not NULL. */
static void run_scene(const char* scene, const char* set, const char* name, const char* script_text, uint64_t frames,
                      sb_view_result* result, picture* png) {
    char script[256], shot[256];
    snprintf(script, sizeof script, "test_viewer_%s.txt", name);
    snprintf(shot, sizeof shot, "test_viewer_%s.png", name);
    write_script(script, script_text);
    const char* sets[] = {"threads=1", set};
    sb_simulation_args args = {.input = scene, .sets = sets, .set_count = set ? 2 : 1};
    sb_view_options o = sb_default_view_options(&args);
    o.width = W, o.height = H, o.script = script, o.screenshot = shot, o.frames = frames;
    sb_error err;
    /* Xvfb under load once refused a window mid-run (glfwInit failed after
     * four windows had opened and closed, in CI's double build): a window
     * that cannot open is tried twice more, a second apart. */
    sb_status status = SB_OK;
    for (int attempt = 0; attempt < 3; attempt++) {
        status = sb_view_run(&o, result, &err);
        if (status == SB_OK || !strstr(err.message, "no display")) break;
        print_message("attempt %d: %s\n", attempt + 1, err.message);
        sleep(1);
    }
    if (status != SB_OK) fail_msg("%s", err.message);
    if (!png) return;
    int channels;
    png->rgb = stbi_load(shot, &png->width, &png->height, &channels, 3);
    assert_non_null(png->rgb);
    assert_int_equal(png->width, W);
    assert_int_equal(png->height, H);
}

/* The default scene. */
static void run_view(const char* name, const char* script_text, uint64_t frames, sb_view_result* result, picture* png) {
    run_scene(SCENE, NULL, name, script_text, frames, result, png);
}

/* Two screenshots of the viewer, the second with the keys of script b. */
static void two_pictures(const char* a, const char* b, uint64_t frames, picture* first, picture* second) {
    sb_view_result r;
    run_view("first", a, frames, &r, first);
    sb_view_result_free(&r);
    run_view("second", b, frames, &r, second);
    sb_view_result_free(&r);
}

static bool background(const unsigned char* p) {
    for (int c = 0; c < 3; c++)
        if (abs(p[c] - BACKGROUND[c]) > 6) return false;
    return true;
}

/* Below the overlay's two lines at the top, above its line at the bottom. */
static bool in_scene(int y) { return y >= 52 && y < H - 30; }

/* A pinhole camera from the result's eye and target: pixel of p. */
static void project(const sb_camera* camera, const double p[3], double pixel[2]) {
    double eye[3], f[3], r[3], u[3], d[3];
    sb_camera_eye(camera, eye);
    for (int k = 0; k < 3; k++) f[k] = camera->target[k] - eye[k], d[k] = p[k] - eye[k];
    double n = tu_norm(f);
    for (int k = 0; k < 3; k++) f[k] /= n;
    tu_cross(f, camera->up, r);
    n = tu_norm(r);
    for (int k = 0; k < 3; k++) r[k] /= n;
    tu_cross(r, f, u);
    double t = tan(0.5 * camera->fov), z = tu_dot(d, f);
    pixel[0] = 0.5 * W + 0.5 * H * tu_dot(d, r) / (z * t);
    pixel[1] = 0.5 * H - 0.5 * H * tu_dot(d, u) / (z * t);
}

static void test_screenshot_shows_the_sheet_where_the_camera_looks(void** state) {
    (void)state;
    sb_view_result r;
    picture png;
    run_view("rest", "0 key space\n", 5, &r, &png);
    assert_true(r.frames >= 1 && r.time == 0.0);
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (uint32_t i = 0; i < r.vertex_count; i++) {
        double pixel[2];
        project(&r.camera, r.positions + 3 * i, pixel);
        for (int k = 0; k < 2; k++) lo[k] = fmin(lo[k], pixel[k]), hi[k] = fmax(hi[k], pixel[k]);
    }
    int seen[2][2] = {{W, H}, {-1, -1}}, colours = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const unsigned char* p = png.rgb + 3 * (y * W + x);
            if (p[0] != png.rgb[0] || p[1] != png.rgb[1] || p[2] != png.rgb[2]) colours++;
            if (!in_scene(y) || background(p)) continue;
            seen[0][0] = x < seen[0][0] ? x : seen[0][0], seen[0][1] = y < seen[0][1] ? y : seen[0][1];
            seen[1][0] = x > seen[1][0] ? x : seen[1][0], seen[1][1] = y > seen[1][1] ? y : seen[1][1];
        }
    printf("sheet: projected x %.1f..%.1f y %.1f..%.1f, drawn x %d..%d y %d..%d\n", lo[0], hi[0], lo[1], hi[1],
           seen[0][0], seen[1][0], seen[0][1], seen[1][1]);
    assert_true(colours > W * H / 20); /* not blank, not one colour */
    TU_ASSERT_NEAR(seen[0][0], lo[0], 3.0);
    TU_ASSERT_NEAR(seen[1][0], hi[0], 3.0);
    TU_ASSERT_NEAR(seen[0][1], lo[1], 3.0);
    TU_ASSERT_NEAR(seen[1][1], hi[1], 3.0);
    free(png.rgb);
    sb_view_result_free(&r);
}

static int dark_pixels(const picture* png) {
    int dark = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const unsigned char* p = png->rgb + 3 * (y * W + x);
            dark += in_scene(y) && p[0] < 90 && p[1] < 90 && p[2] < 90;
        }
    return dark;
}

static void test_f2_hides_the_edges(void** state) {
    (void)state;
    picture with, without;
    two_pictures("0 key space\n", "0 key space\n0 key F2\n", 5, &with, &without);
    int a = dark_pixels(&with), b = dark_pixels(&without);
    printf("dark pixels: %d with edges, %d without\n", a, b);
    assert_true(a > 1000 && b < a / 10);
    free(with.rgb);
    free(without.rgb);
}

/* Strongly red and strongly blue pixels in the colour scale's column. */
static void scale_colours(const picture* png, int* red, int* blue) {
    *red = *blue = 0;
    for (int y = 100; y < 380 && y < H; y++)
        for (int x = W - 50; x < W - 26; x++) {
            const unsigned char* p = png->rgb + 3 * (y * W + x);
            *red += p[0] > 200 && p[1] < 80 && p[2] < 80;
            *blue += p[2] > 200 && p[0] < 80 && p[1] < 80;
        }
}

static void test_f3_shows_the_colour_scale(void** state) {
    (void)state;
    picture plain, strained;
    two_pictures("0.05 quit\n", "0.05 key F3\n0.05 quit\n", 0, &plain, &strained);
    int red0, blue0, red1, blue1;
    scale_colours(&plain, &red0, &blue0);
    scale_colours(&strained, &red1, &blue1);
    printf("scale column: red %d, blue %d without F3; red %d, blue %d with\n", red0, blue0, red1, blue1);
    assert_true(red0 == 0 && blue0 == 0 && red1 > 50 && blue1 > 50);
    free(plain.rgb);
    free(strained.rgb);
}

/* h: the list of keys on a white card over most of the picture. */
static void test_h_shows_the_keys(void** state) {
    (void)state;
    picture plain, help;
    two_pictures("0 key space\n", "0 key space\n0 key h\n", 5, &plain, &help);
    int white[2] = {0, 0};
    for (int i = 0; i < W * H; i++)
        for (int k = 0; k < 2; k++) {
            const unsigned char* p = (k ? help.rgb : plain.rgb) + 3 * i;
            white[k] += p[0] > 240 && p[1] > 240 && p[2] > 240;
        }
    printf("white pixels: %d without h, %d with\n", white[0], white[1]);
    assert_true(white[0] < W * H / 100 && white[1] > W * H / 4);
    free(plain.rgb);
    free(help.rgb);
}

/* o: the statistics' dark text at the top is gone, and back after o again. */
static int top_ink(const picture* p) {
    int dark = 0;
    for (int y = 0; y < 50; y++)
        for (int x = 0; x < W; x++) {
            const unsigned char* c = p->rgb + 3 * (y * W + x);
            dark += c[0] < 60 && c[1] < 60 && c[2] < 60;
        }
    return dark;
}

static void test_o_hides_the_statistics(void** state) {
    (void)state;
    picture shown, hidden;
    two_pictures("0 key space\n0 key o\n0 key o\n", "0 key space\n0 key o\n", 5, &shown, &hidden);
    printf("dark pixels at the top: %d with the statistics, %d without\n", top_ink(&shown), top_ink(&hidden));
    assert_true(top_ink(&shown) > 300 && top_ink(&hidden) == 0);
    free(shown.rgb);
    free(hidden.rgb);
}

static void test_g_turns_gravity_off(void** state) {
    (void)state;
    sb_view_result r;
    run_view("gravity_off", "0 key g\n0.2 quit\n", 0, &r, NULL);
    assert_true(r.time >= 0.2 && r.step > 0);
    double largest = 0.0;
    for (uint32_t i = 0; i < r.vertex_count; i++) largest = fmax(largest, fabs(r.velocities[3 * i + 2]));
    printf("gravity off: t = %.3f s, largest |vz| %g m/s\n", r.time, largest);
    assert_true(largest < 1e-6); /* rounding of the rest state's forces; falling, it is ~2 m/s */
    sb_view_result_free(&r);
}

static double mean_z(const sb_view_result* r) {
    double sum = 0.0;
    for (uint32_t i = 0; i < r->vertex_count; i++) sum += r->positions[3 * i + 2];
    return sum / r->vertex_count;
}

static void test_r_reverses_gravity(void** state) {
    (void)state;
    sb_view_result r;
    run_view("reversed", "0 key r\n0.2 quit\n", 0, &r, NULL);
    printf("gravity reversed: t = %.3f s, mean z %.4f m\n", r.time, mean_z(&r));
    assert_true(r.time >= 0.2 && mean_z(&r) > 0.02);
    sb_view_result_free(&r);
}

/* The middle vertex (15, 15) of the sheet at rest, pressed, then the
 * cursor 60 pixels to its right: it follows toward the cursor's point. */
static void test_scripted_drag_pulls_the_vertex(void** state) {
    (void)state;
    const uint32_t middle = 15 * 30 + 15;
    double rest[3] = {15.0 / 29.0, 15.0 / 29.0, 0.0}, lo[3] = {0, 0, 0}, hi[3] = {1, 1, 0}, up[3] = {0, 0, 1}, pixel[2];
    sb_camera camera = sb_camera_fit(lo, hi, up);
    project(&camera, rest, pixel);
    char script[256];
    snprintf(script, sizeof script, "0 press %.1f %.1f\n0.02 move %.1f %.1f\n0.4 quit\n", pixel[0], pixel[1],
             pixel[0] + 60, pixel[1]);
    sb_view_result r;
    run_view("drag", script, 0, &r, NULL);
    assert_int_equal(r.picked, middle);
    const double* x = r.positions + 3 * middle;
    double moved = x[0] - rest[0], wanted = r.target[0] - rest[0];
    printf("drag: vertex %lld, target x %.3f m (%.3f from rest), vertex x %.3f m (moved %.3f) at t = %.3f s\n",
           (long long)r.picked, r.target[0], wanted, x[0], moved, r.time);
    assert_true(wanted > 0.1 && moved > 0.35 * wanted);
    sb_view_result_free(&r);
}

/* haptics_probe.yaml with the mouse device: the probe (a 5 mm sphere 7 mm
 * above the sheet's middle) pressed and dragged 60 pixels down the screen
 * over 0.6 s (29 mm at the probe) pushes the sheet's middle vertex more
 * than 5 mm down. */
static void test_mouse_moves_the_haptic_tool(void** state) {
    (void)state;
    const char* scene = SB_SOURCE_DIR "/scenes/haptics_probe.yaml";
    double probe[3] = {0.05, 0.05, 0.012}, lo[3] = {0, 0, 0}, hi[3] = {0.1, 0.1, 0}, up[3] = {0, 0, 1}, pixel[2];
    sb_camera camera = sb_camera_fit(lo, hi, up);
    project(&camera, probe, pixel);
    char script[1024];
    int used = snprintf(script, sizeof script, "0 press %.1f %.1f\n", pixel[0], pixel[1]);
    for (int k = 1; k <= 12; k++) /* 5 pixels every 50 ms: a hand's pace, the proxy stays on the sheet */
        used += snprintf(script + used, sizeof script - (size_t)used, "%.2f move %.1f %.1f\n", 0.05 * k, pixel[0],
                         pixel[1] + 5.0 * k);
    snprintf(script + used, sizeof script - (size_t)used, "0.8 quit\n");
    sb_view_result r;
    run_scene(scene, "haptics.device=mouse", "mouse", script, 0, &r, NULL);
    const uint32_t middle = 10 * 21 + 10;
    printf("mouse device: %llu frames, cursor target z %.4f m, the sheet's middle at z %.4f m (t = %.3f s)\n",
           (unsigned long long)r.frames, r.target[2], r.positions[3 * middle + 2], r.time);
    assert_true(r.picked < 0 && r.target[2] < -0.005 && r.positions[3 * middle + 2] < -0.005);
    sb_view_result_free(&r);
}

/* Without a display the program says so in one line and exits with 2. */
static void test_no_display_is_said(void** state) {
    (void)state;
    char command[1024], text[1024];
    snprintf(command, sizeof command, "env -u DISPLAY -u WAYLAND_DISPLAY %s view " SCENE " 2>&1; echo exit $?",
             SB_PROGRAM);
    FILE* p = popen(command, "r");
    assert_non_null(p);
    size_t n = fread(text, 1, sizeof text - 1, p);
    text[n] = '\0';
    pclose(p);
    const char* expected = "softbond: view: no display to open a window on (is DISPLAY set? headless: xvfb-run -a "
                           "softbond view ...)";
    assert_memory_equal(text, expected, strlen(expected));
    assert_non_null(strstr(text, "\nexit 2\n"));
    assert_ptr_equal(strchr(text, '\n'), strstr(text, "\nexit 2\n")); /* one line, then the status */
}

static void test_script_errors_name_the_line(void** state) {
    (void)state;
    write_script("test_viewer_bad.txt", "# a comment\n0 key F1\n0.5 press 10\n");
    sb_input_script s;
    sb_error err;
    assert_int_equal(sb_input_script_load("test_viewer_bad.txt", &s, &err), SB_ERR_INVALID);
    assert_non_null(strstr(err.message, "test_viewer_bad.txt:3:"));
    write_script("test_viewer_bad.txt", "0.5 key F1\n0.1 key q\n");
    assert_int_equal(sb_input_script_load("test_viewer_bad.txt", &s, &err), SB_ERR_INVALID);
    assert_non_null(strstr(err.message, "test_viewer_bad.txt:2: time 0.1 is before"));
    write_script("test_viewer_bad.txt", "0 key F6\n");
    assert_int_equal(sb_input_script_load("test_viewer_bad.txt", &s, &err), SB_ERR_INVALID);
    assert_non_null(strstr(err.message, "test_viewer_bad.txt:1: expected key NAME"));
}

/* A solver that fails: its message on stderr, exit 3 (as softbond run's), and
 * in the screenshot in red on a white panel, wrapped inside the window. */
static void test_solver_failure_exits_3(void** state) {
    (void)state;
    char command[1024], text[2048];
    remove("test_viewer_failure.png");
    snprintf(command, sizeof command,
             "%s view " SCENE " --set dt=0.01 --set threads=1 --screenshot test_viewer_failure.png --frames 10 "
             "--size %dx%d --render-share 1 2>&1; echo exit $?",
             SB_PROGRAM, W, H);
    FILE* p = popen(command, "r");
    assert_non_null(p);
    size_t n = fread(text, 1, sizeof text - 1, p);
    text[n] = '\0';
    pclose(p);
    if (!strstr(text, "softbond: step ") || !strstr(text, "the time step is too large") || !strstr(text, "\nexit 3\n"))
        fail_msg("expected the solver's failure and exit 3, got: %s", text);
    int w, h, channels;
    unsigned char* rgb = stbi_load("test_viewer_failure.png", &w, &h, &channels, 3);
    assert_non_null(rgb);
    int red = 0, red_right = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const unsigned char* c = rgb + 3 * ((size_t)y * (size_t)w + (size_t)x);
            if (c[0] > 150 && c[1] < 60 && c[2] < 60) {
                red++;
                red_right += x >= w - 4;
            }
        }
    stbi_image_free(rgb);
    TU_ASSERT_LE(200, red);         /* the message is drawn */
    assert_int_equal(red_right, 0); /* and wrapped, not cut at the window's edge */
}

/* In a window narrower than the statistics' lines they wrap: no dark ink
 * of the text in the window's last columns at the top (the lines were cut
 * there), and the text is drawn. */
static void test_statistics_wrap_in_a_narrow_window(void** state) {
    (void)state;
    char command[1024];
    remove("test_viewer_narrow.png");
    snprintf(command, sizeof command,
             "%s view " SCENE " --set threads=1 --screenshot test_viewer_narrow.png --frames 3 --size 300x240 "
             "--render-share 1 > /dev/null 2>&1",
             SB_PROGRAM);
    assert_int_equal(system(command), 0);
    int w, h, channels;
    unsigned char* rgb = stbi_load("test_viewer_narrow.png", &w, &h, &channels, 3);
    assert_non_null(rgb);
    int ink = 0, ink_right = 0;
    for (int y = 0; y < 100 && y < h; y++)
        for (int x = 0; x < w; x++) {
            const unsigned char* c = rgb + 3 * ((size_t)y * (size_t)w + (size_t)x);
            bool dark = c[0] < 60 && c[1] < 60 && c[2] < 60;
            ink += dark;
            ink_right += dark && x >= w - 6;
        }
    stbi_image_free(rgb);
    TU_ASSERT_LE(300, ink);         /* the statistics are drawn */
    assert_int_equal(ink_right, 0); /* and wrapped, not cut at the window's edge */
}

/* The scene's part of two pictures (below the overlay's lines at the top, above its line at the bottom) differ in this
 * many pixels. */
static int scene_differences(const picture* a, const picture* b) {
    int differ = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; in_scene(y) && x < W; x++)
            differ += memcmp(a->rgb + 3 * (y * W + x), b->rgb + 3 * (y * W + x), 3) != 0;
    return differ;
}

static void read_picture(const char* path, picture* png) {
    int channels;
    png->rgb = stbi_load(path, &png->width, &png->height, &channels, 3);
    if (!png->rgb) fail_msg("cannot read %s", path);
    assert_int_equal(png->width, W);
}

/* The script's events wait for the simulation's clock: pausing at 0.15 s
 * twice pauses at the same step, and p saves the same picture. */
static void test_script_replays_identically(void** state) {
    (void)state;
    sb_view_result r[2];
    picture shot[2];
    remove("default_001.png"), remove("default_002.png");
    for (int k = 0; k < 2; k++) run_view("replay", "0.15 key space\n0.15 key p\n", 90, &r[k], NULL);
    printf("paused at t = %.17g s (step %llu) and %.17g s (step %llu)\n", r[0].time, (unsigned long long)r[0].step,
           r[1].time, (unsigned long long)r[1].step);
    assert_true(r[0].time >= 0.15 && r[0].time < 0.151);
    assert_true(r[0].time == r[1].time);
    assert_int_equal(r[0].step, r[1].step);
    assert_int_equal(r[0].vertex_count, r[1].vertex_count);
    assert_memory_equal(r[0].positions, r[1].positions, 3 * (size_t)r[0].vertex_count * sizeof(double));
    read_picture("default_001.png", &shot[0]); /* p: SCENE_NNN.png, the first number not taken */
    read_picture("default_002.png", &shot[1]);
    assert_int_equal(scene_differences(&shot[0], &shot[1]), 0);
    for (int k = 0; k < 2; k++) {
        free(shot[k].rgb);
        sb_view_result_free(&r[k]);
    }
}

static void test_n_takes_one_step(void** state) {
    (void)state;
    sb_view_result r;
    run_view("single", "0 key space\n0 key n\n0 key n\n0 key n\n", 20, &r, NULL);
    assert_int_equal(r.step, 3);
    sb_view_result_free(&r);
}

/* l at 0.1 s (then space, before the reload is done): the scene anew, paused at its start. */
static void test_l_reloads_the_scene(void** state) {
    (void)state;
    sb_view_result r;
    run_view("reload", "0.1 key l\n0.1 key space\n", 40, &r, NULL);
    assert_int_equal(r.step, 0);
    assert_true(r.time == 0.0);
    sb_view_result_free(&r);
    run_view("no_reload", "0.1 key space\n", 40, &r, NULL);
    assert_true(r.time >= 0.1);
    sb_view_result_free(&r);
}

static int scene_pixels(const picture* png) {
    int count = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; in_scene(y) && x < W; x++) count += !background(png->rgb + 3 * (y * W + x));
    return count;
}

static void test_net_is_drawn_as_edges(void** state) {
    (void)state;
    sb_view_result r;
    picture with, without;
    run_scene(SB_SOURCE_DIR "/scenes/net.yaml", NULL, "net", "0 key space\n", 5, &r, &with);
    const double ball[3] = {0.3, 0.6, 3.2}; /* scenes/net.yaml's ball, 2.2 m above the net */
    double pixel[2];
    project(&r.camera, ball, pixel);
    printf("the ball at pixel (%.0f, %.0f)\n", pixel[0], pixel[1]);
    assert_true(pixel[0] > 0 && pixel[0] < W && pixel[1] > 52 && pixel[1] < H - 30);
    sb_view_result_free(&r);
    run_scene(SB_SOURCE_DIR "/scenes/net.yaml", NULL, "net_f2", "0 key F2\n0 key space\n", 5, &r, &without);
    printf("net: %d pixels with its edges, %d without\n", scene_pixels(&with), scene_pixels(&without));
    TU_ASSERT_LE(400, scene_pixels(&with));
    TU_ASSERT_LE(scene_pixels(&without), 150); /* the ball only: no faces */
    free(with.rgb), free(without.rgb);
    sb_view_result_free(&r);
}

/* --screenshot onto /dev/full: one line naming the file, exit 1 (not 0). */
static void test_screenshot_onto_a_full_device_fails(void** state) {
    (void)state;
    char command[1024], text[2048];
    snprintf(command, sizeof command,
             "%s view " SCENE " --set threads=1 --screenshot /dev/full --frames 2 --size %dx%d 2>&1; echo exit $?",
             SB_PROGRAM, W, H);
    FILE* p = popen(command, "r");
    assert_non_null(p);
    size_t n = fread(text, 1, sizeof text - 1, p);
    text[n] = '\0';
    pclose(p);
    assert_string_equal(text, "softbond: /dev/full: cannot write: No space left on device\nexit 1\n");
}

int main(void) {
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_script_errors_name_the_line),
        cmocka_unit_test(test_no_display_is_said),
        cmocka_unit_test(test_solver_failure_exits_3),
        cmocka_unit_test(test_statistics_wrap_in_a_narrow_window),
        cmocka_unit_test(test_screenshot_onto_a_full_device_fails),
        cmocka_unit_test(test_script_replays_identically),
        cmocka_unit_test(test_n_takes_one_step),
        cmocka_unit_test(test_l_reloads_the_scene),
        cmocka_unit_test(test_net_is_drawn_as_edges),
        cmocka_unit_test(test_screenshot_shows_the_sheet_where_the_camera_looks),
        cmocka_unit_test(test_f2_hides_the_edges),
        cmocka_unit_test(test_f3_shows_the_colour_scale),
        cmocka_unit_test(test_h_shows_the_keys),
        cmocka_unit_test(test_o_hides_the_statistics),
        cmocka_unit_test(test_g_turns_gravity_off),
        cmocka_unit_test(test_r_reverses_gravity),
        cmocka_unit_test(test_scripted_drag_pulls_the_vertex),
        cmocka_unit_test(test_mouse_moves_the_haptic_tool),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
