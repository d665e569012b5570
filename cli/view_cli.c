/* `softbond view SCENE.yaml`: the arguments, then the viewer (viewer/view.h). */
#include "cli/cli.h"
#include "common/error.h"
#include "viewer/view.h"

#include <stdlib.h>

void sb_cli_view_usage(FILE* stream) {
    fprintf(stream, "usage: softbond view SCENE.yaml [--set key=value]... [--threads N] [--size WxH]\n"
                    "                     [--render-share X] [--screenshot FILE.png --frames N] [--script FILE]\n"
                    "Shows the scene running in a window (OpenGL 3.3), the simulation on its own thread\n"
                    "at the wall clock's pace (or as fast as it can: the real-time factor is shown).\n"
                    "Keys: F1 vertices, F2 edges, F3 edges coloured by strain, F4 faces, F5 texture,\n"
                    "r reverse gravity, s stop/resume the bodies, g gravity on/off, space pause,\n"
                    "n one step, backspace reset, p screenshot (SCENE_NNN.png), l reload the scene,\n"
                    "c camera back, h the list of keys, o statistics on/off, escape quit. Mouse: drag a\n"
                    "vertex (a spring to the cursor), drag elsewhere to orbit, shift+drag to pan,\n"
                    "wheel to zoom; with haptics.device: mouse, drag moves the haptic tool.\n"
                    "--screenshot FILE.png saves the last frame drawn, when the viewer ends: after\n"
                    "--frames N frames, at escape or when the window closes; --frames N stops after N\n"
                    "frames. A solver failure is shown in the window, and when the viewer ends it is\n"
                    "printed on stderr and the exit status is 3, as softbond run's;\n"
                    "--script FILE plays keys and mouse events at simulated times (docs/viewer.md);\n"
                    "the simulation waits at each event's time, so a script replays identically.\n"
                    "--render-share X: drawing takes at most this share of the wall clock (default 0.15;\n"
                    "1 = no limit): a slow software renderer lowers its frame rate, not the solver's.\n"
                    "Headless: xvfb-run -a softbond view ...\n");
}

static sb_status view_options(const sb_cli_args* args, const sb_simulation_args* sim_args, sb_view_options* o,
                              sb_error* err) {
    *o = sb_default_view_options(sim_args);
    if (args->frames) {
        char* end;
        long long frames = strtoll(args->frames, &end, 10);
        if (end == args->frames || *end != '\0' || frames < 1)
            return sb_error_set(err, SB_ERR_INVALID, "--frames: expected a whole number >= 1, got '%s'", args->frames);
        o->frames = (uint64_t)frames;
    }
    if (args->render_share) {
        char* end;
        o->render_share = strtod(args->render_share, &end);
        if (end == args->render_share || *end != '\0' || !(o->render_share > 0.0 && o->render_share <= 1.0))
            return sb_error_set(err, SB_ERR_INVALID, "--render-share: expected a number in (0, 1], got '%s'",
                                args->render_share);
    }
    o->screenshot = args->screenshot;
    o->script = args->script;
    return args->size ? sb_cli_size(args->size, &o->width, &o->height, err) : SB_OK;
}

int sb_cli_view(int argc, char** argv) {
    static const char* const accepted[] = {"--threads", "--screenshot",   "--frames", "--script",
                                           "--size",    "--render-share", NULL};
    sb_cli_args args;
    sb_error err;
    int code = SB_EXIT_OK;
    sb_view_options options;
    sb_status parsed = sb_cli_parse(argc, argv, accepted, &args, &err);
    sb_simulation_args sim_args = sb_cli_simulation_args(&args); /* the options point at it */
    if (parsed != SB_OK || view_options(&args, &sim_args, &options, &err) != SB_OK)
        code = sb_cli_fail(SB_EXIT_INPUT, &err);
    else if (args.help)
        sb_cli_view_usage(stdout);
    else {
        sb_status status = sb_view_run(&options, NULL, &err);
        if (status != SB_OK)
            code = sb_cli_fail(status == SB_ERR_UNSTABLE ? SB_EXIT_SOLVER
                               : status == SB_ERR_IO     ? SB_EXIT_FAILURE
                                                         : SB_EXIT_INPUT,
                               &err);
    }
    sb_cli_args_free(&args);
    return code;
}
