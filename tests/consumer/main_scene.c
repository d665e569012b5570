/* A program outside the project that loads a YAML scene through the
 * installed scene library and runs it a few steps: the scene given as its
 * argument is a 5 x 4 sheet with dt 0.001 s; the override halves dt. */
#include <stdio.h>
#include <softbond/scene.h>
#include <softbond/softbond.h>

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    const char* const sets[] = {"dt=0.0005"};
    sb_scene_file* scene;
    sb_error err;
    if (sb_scene_file_load(argv[1], sets, 1, &scene, &err) != SB_OK) {
        fprintf(stderr, "consumer_scene: %s\n", err.message);
        return 1;
    }
    sb_solver* solver = sb_solver_create(sb_scene_file_model(scene), sb_scene_file_solver_def(scene), &err);
    int ok = solver && sb_model_vertex_count(sb_scene_file_model(scene)) == 20 && sb_scene_file_dt(scene) == 0.0005;
    for (int i = 0; ok && i < 10; i++) ok = sb_solver_advance(solver, sb_scene_file_dt(scene)) == SB_OK;
    sb_solver_destroy(solver);
    sb_scene_file_destroy(scene);
    printf("consumer_scene: %s\n", ok ? "ok" : "wrong scene");
    return ok ? 0 : 1;
}
