/* sb_mesh: the plain indexed triangle mesh that generators and importers
 * produce. It owns two malloc'd arrays and nothing else. */
#include <stdlib.h>
#include <string.h>

#include "softbond/mesh.h"

void sb_mesh_free(sb_mesh* mesh) {
    if (mesh == NULL) {
        return;
    }
    free(mesh->positions);
    free(mesh->triangles);
    memset(mesh, 0, sizeof *mesh);
}
