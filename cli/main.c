/* The `softbond` program: `run` a scene, `view` it running, `film` it,
 * `eval` a mesh's energies and forces, `info` on a mesh, `tetra` a closed
 * surface, list the scene `keys`. See docs/ (scenes.md, scene_keys.md,
 * viewer.md, commands.md). */
#include "cli/cli.h"
#include "scenes/suggest.h"

#include <string.h>

static void usage(FILE* stream) {
    fprintf(stream,
            "usage: softbond COMMAND ARGUMENTS... (softbond COMMAND --help describes one)\n"
            "Soft bodies with molecular-mechanics bonded terms: run, watch and film YAML scenes.\n"
            "\n"
            "Commands:\n"
            "  softbond run SCENE.yaml [--set key=value]... [--output DIR] [--threads N]\n"
            "               [--budget-ms X [--max-error M]] [--no-realtime] [--checkpoint-every T]\n"
            "               [--end-positions FILE.csv]\n"
            "  softbond run SCENE.yaml [--set key=value]... --resume DIR [--threads N]\n"
            "      simulate a scene, write its frames and log.csv\n"
            "  softbond view SCENE.yaml [--set key=value]... [--threads N] [--size WxH]\n"
            "               [--render-share X] [--screenshot FILE.png --frames N] [--script FILE]\n"
            "      show the scene running in a window\n"
            "  softbond film SCENE.yaml [--set key=value]... [--movie OUT.mp4] [--size WxH] [--fps F]\n"
            "               [--eye x,y,z] [--target x,y,z] [--output DIR] [--threads N]\n"
            "      render the scene with POV-Ray into an MP4\n"
            "  softbond eval MESH [--set key=value]... [--positions POS.csv] [--forces OUT.csv] [--fast]\n"
            "      a mesh's energies (and forces) at given positions\n"
            "  softbond info MESH\n"
            "      what a mesh file holds\n"
            "  softbond tetra IN OUT [--quality Q] [--max-volume V]\n"
            "      fill a closed surface with tetrahedra (TetGen)\n"
            "  softbond keys [KEY|PREFIX] [--markdown]\n"
            "      every scene key: type, default, unit, meaning\n"
            "  softbond sweep SWEEP.yaml [--set key=value]... [--output DIR | --resume DIR]\n"
            "               [--workers N] [--threads N]      (also under mpirun -np N)\n"
            "      run a scene over a design of varied keys: one CSV row per case, charts\n"
            "  softbond fit FIT.yaml [--set key=value]... [--output DIR] [--threads N]   (also under mpirun)\n"
            "      fit scene keys so a log.csv curve follows a measured one (NLopt)\n"
            "\n"
            "Options:\n"
            "  -h, --help     this help (after a command: that command's)\n"
            "  --version      the version and the machine\n"
            "\n"
            "Exit status: 0 done, 1 an output could not be written, 2 bad input (one line on\n"
            "stderr names the file and line), 3 the solver failed.\n"
            "Manual: docs/ in the source, share/doc/softbond when installed; scenes in\n"
            "share/softbond/scenes.\n");
}

int main(int argc, char** argv) {
    if (argc < 2) {
        usage(stderr);
        return SB_EXIT_INPUT;
    }
    const char* command = argv[1];
    if (strcmp(command, "run") == 0) return sb_cli_run(argc - 1, argv + 1);
    if (strcmp(command, "eval") == 0) return sb_cli_eval(argc - 1, argv + 1);
    if (strcmp(command, "info") == 0) return sb_cli_info(argc - 1, argv + 1);
    if (strcmp(command, "tetra") == 0) return sb_cli_tetra(argc - 1, argv + 1);
    if (strcmp(command, "view") == 0) return sb_cli_view(argc - 1, argv + 1);
    if (strcmp(command, "film") == 0) return sb_cli_film(argc - 1, argv + 1);
    if (strcmp(command, "keys") == 0) return sb_cli_keys(argc - 1, argv + 1);
    if (strcmp(command, "sweep") == 0) return sb_cli_sweep(argc - 1, argv + 1);
    if (strcmp(command, "fit") == 0) return sb_cli_fit(argc - 1, argv + 1);
    if (strcmp(command, "--help") == 0 || strcmp(command, "-h") == 0) {
        usage(stdout);
        return SB_EXIT_OK;
    }
    if (strcmp(command, "--version") == 0) {
        char machine[256];
        sb_runtime_describe(machine, sizeof machine);
        printf("softbond %s\nmachine: %s\n", SB_VERSION_STRING, machine);
        return SB_EXIT_OK;
    }
    static const char* const commands[] = {"run",   "view",  "film", "eval",   "info",
                                           "tetra", "sweep", "fit",  "--help", "--version"};
    const char* near = sb_suggest(command, commands, sizeof commands / sizeof commands[0]);
    fprintf(stderr, "softbond: unknown command '%s'%s%s%s (see softbond --help)\n", command,
            near ? " (did you mean '" : "", near ? near : "", near ? "'?)" : "");
    return SB_EXIT_INPUT;
}
