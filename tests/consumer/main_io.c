/* A program outside the project that reads a mesh file through the
 * installed io library: the OBJ given as its argument has 4 vertices and 2
 * triangles. */
#include <stdio.h>
#include <softbond/softbond.h>

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    sb_mesh mesh;
    sb_error err;
    if (sb_mesh_load(argv[1], &mesh, &err) != SB_OK) {
        fprintf(stderr, "consumer_io: %s\n", err.message);
        return 1;
    }
    int ok = mesh.vertex_count == 4 && mesh.triangle_count == 2;
    sb_mesh_free(&mesh);
    printf("consumer_io: %s\n", ok ? "ok" : "wrong counts");
    return ok ? 0 : 1;
}
