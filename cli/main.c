/* The `softbond` program: `run` a scene, `view` it running, `film` it,
 * `eval` a mesh's energies and forces, `info` on a mesh, `tetra` a closed
 * surface. See README.md ("Running a scene", "Viewer", "softbond eval",
 * "softbond info", "softbond tetra"). */
#include "cli/cli.h"

#include <string.h>

static void usage(FILE* stream) {
    fprintf(stream, "usage: softbond run SCENE.yaml [--set key=value]... [--output DIR] [--threads N]\n"
                    "       softbond view SCENE.yaml [--set key=value]... [--screenshot FILE.png --frames N]\n"
                    "                          [--script FILE]\n"
                    "       softbond film SCENE.yaml [--movie OUT.mp4] [--size WxH] [--fps F]\n"
                    "       softbond eval MESH [--set key=value]... [--positions POS.csv]\n"
                    "                          [--forces OUT.csv] [--fast]\n"
                    "       softbond info MESH\n"
                    "       softbond tetra IN OUT [--quality Q] [--max-volume V]\n"
                    "       softbond --help | --version\n"
                    "Soft bodies with molecular-mechanics bonded terms. `softbond COMMAND --help`\n"
                    "describes a command.\n");
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
    fprintf(stderr, "softbond: unknown command '%s' (see softbond --help)\n", command);
    return SB_EXIT_INPUT;
}
