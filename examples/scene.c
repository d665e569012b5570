/* scene: runs a scene file through the scene library, as `softbond run`
 * would, without writing frames: `scene SCENE.yaml [key=value]...`.
 * Build: cc scene.c $(pkg-config --cflags --libs softbond_scene) -o scene */
#include <softbond/scene.h>
#include <softbond/softbond.h>

#include <stdio.h>
#include <stdlib.h>

int main(int argc, char** argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: scene SCENE.yaml [key=value]...\n");
        return 2;
    }
    sb_error err;
    sb_scene_file* scene = NULL;
    /* argv[2..]: overrides as `softbond run --set` takes them */
    if (sb_scene_file_load(argv[1], (const char* const*)argv + 2, (size_t)(argc - 2), &scene, &err) != SB_OK) {
        fprintf(stderr, "scene: %s\n", err.message); /* names the file and line */
        return 2;
    }
    int code = EXIT_FAILURE;
    sb_solver* solver = sb_solver_create(sb_scene_file_model(scene), sb_scene_file_solver_def(scene), &err);
    if (!solver) {
        fprintf(stderr, "scene: %s\n", err.message);
        goto out;
    }
    double dt = sb_scene_file_dt(scene), duration = sb_scene_file_duration(scene);
    long steps = (long)(duration / dt + 0.5);
    for (long i = 0; i < steps; i++) {
        if (sb_solver_advance(solver, dt) != SB_OK) {
            fprintf(stderr, "scene: %s\n", sb_solver_error(solver));
            goto out;
        }
    }
    sb_energies e = sb_solver_energies(solver);
    printf("scene %s: %u vertices, %ld steps of %g s, t = %g s, kinetic %.6g J, total %.6g J\n",
           sb_scene_file_name(scene), sb_solver_vertex_count(solver), steps, dt, sb_solver_time(solver), e.kinetic,
           sb_energies_total(&e));
    code = EXIT_SUCCESS;
out:
    sb_solver_destroy(solver);
    sb_scene_file_destroy(scene);
    return code;
}
