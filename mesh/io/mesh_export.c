/* sb_mesh_export: one table maps a format name to its extension and its
 * writer, either an assimp exporter id or one of softbond's text writers
 * (IRIT, POV-Ray). The text formats are written through an atomic file
 * (common/atomic_file.h: checked writes, NAME.tmp renamed); making a set
 * of frames appear atomically is the caller's business (softbond run
 * stages them).
 *
 * Assimp is given a scene built here in C: one mesh of triangles (float
 * positions, assimp's ai_real, and area-weighted vertex normals: without
 * them the OBJ exporter runs assimp's normal generation, which gave a
 * vertex of a bent 3 x 3 sheet one face's normal instead of a blend), one
 * empty material (the OBJ and glTF exporters index it), one root node with
 * the identity transform. It is freed here too; assimp only reads it.
 * Assimp's C export call keeps no error text, so a failed export is
 * reported by format and path, after checking that the path can be opened
 * for writing (which names the system's reason when it cannot). */
#define _POSIX_C_SOURCE 200809L
#include "mesh/io/mesh_writers.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <assimp/cexport.h>
#include <assimp/scene.h>

#include "common/atomic_file.h"
#include "common/error.h"

typedef struct export_format {
    const char* name;
    const char* extension;
    const char* assimp_id; /* NULL: a text writer */
    void (*write_text)(FILE* f, const sb_mesh* mesh, const sb_mesh_export_def* def);
} export_format;

static const export_format formats[] = {
    {"ply", ".ply", "plyb", NULL}, {"obj", ".obj", "obj", NULL},          {"gltf", ".gltf", "gltf2", NULL},
    {"glb", ".glb", "glb2", NULL}, {"irit", ".itd", NULL, sb_irit_write}, {"pov", ".pov", NULL, sb_pov_write},
};

static const export_format* find_format(const char* name) {
    for (size_t i = 0; i < sizeof formats / sizeof formats[0]; i++)
        if (strcmp(formats[i].name, name) == 0) return &formats[i];
    return NULL;
}

const char* sb_mesh_export_extension(const char* format) {
    const export_format* f = format ? find_format(format) : NULL;
    return f ? f->extension : NULL;
}

/* ---- assimp --------------------------------------------------------------- */

typedef struct assimp_scene {
    struct aiScene scene;
    struct aiNode root;
    struct aiMesh mesh;
    struct aiMaterial material;
    struct aiMesh* mesh_list[1];
    struct aiMaterial* material_list[1];
    unsigned int root_meshes[1];
} assimp_scene;

static void assimp_scene_free(assimp_scene* s) {
    free(s->mesh.mVertices);
    free(s->mesh.mNormals);
    free(s->mesh.mFaces);
    free(s);
}

/* Each vertex's normal: the sum of its triangles' (b - a) x (c - a), made
 * unit; m->mNormals starts zeroed. */
static void fill_normals(struct aiMesh* m, const sb_mesh* mesh, const double* x) {
    for (uint32_t t = 0; t < mesh->triangle_count; t++) {
        const uint32_t* v = mesh->triangles + 3 * t;
        const double *a = x + 3 * (size_t)v[0], *b = x + 3 * (size_t)v[1], *c = x + 3 * (size_t)v[2];
        double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        struct aiVector3D f = {(ai_real)(u[1] * w[2] - u[2] * w[1]), (ai_real)(u[2] * w[0] - u[0] * w[2]),
                               (ai_real)(u[0] * w[1] - u[1] * w[0])};
        for (int corner = 0; corner < 3; corner++) {
            struct aiVector3D* n = &m->mNormals[v[corner]];
            *n = (struct aiVector3D){n->x + f.x, n->y + f.y, n->z + f.z};
        }
    }
    for (uint32_t i = 0; i < mesh->vertex_count; i++) {
        struct aiVector3D* n = &m->mNormals[i];
        double length = sqrt((double)n->x * n->x + (double)n->y * n->y + (double)n->z * n->z);
        ai_real s = length > 0.0 ? (ai_real)(1.0 / length) : 0;
        *n = (struct aiVector3D){n->x * s, n->y * s, n->z * s};
    }
}

static void fill_geometry(struct aiMesh* m, const sb_mesh* mesh, const double* positions, unsigned int* indices) {
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        m->mVertices[v] = (struct aiVector3D){(ai_real)positions[3 * v], (ai_real)positions[3 * v + 1],
                                              (ai_real)positions[3 * v + 2]};
    for (uint32_t t = 0; t < mesh->triangle_count; t++) {
        for (int c = 0; c < 3; c++) indices[3 * t + c] = mesh->triangles[3 * t + c];
        m->mFaces[t] = (struct aiFace){3, indices + 3 * t};
    }
}

/* The faces' index arrays live in one block after the faces. */
static assimp_scene* assimp_scene_make(const sb_mesh* mesh, const double* positions) {
    assimp_scene* s = calloc(1, sizeof *s);
    size_t faces = mesh->triangle_count;
    if (!s) return NULL;
    size_t vertices = mesh->vertex_count ? mesh->vertex_count : 1;
    s->mesh.mVertices = malloc(vertices * sizeof(struct aiVector3D));
    s->mesh.mNormals = calloc(vertices, sizeof(struct aiVector3D));
    s->mesh.mFaces = malloc((faces ? faces : 1) * (sizeof(struct aiFace) + 3 * sizeof(unsigned int)));
    if (!s->mesh.mVertices || !s->mesh.mNormals || !s->mesh.mFaces) {
        assimp_scene_free(s);
        return NULL;
    }
    s->mesh.mPrimitiveTypes = aiPrimitiveType_TRIANGLE;
    s->mesh.mNumVertices = mesh->vertex_count;
    s->mesh.mNumFaces = mesh->triangle_count;
    fill_geometry(&s->mesh, mesh, positions, (unsigned int*)(s->mesh.mFaces + faces));
    fill_normals(&s->mesh, mesh, positions);
    s->mesh_list[0] = &s->mesh;
    s->material_list[0] = &s->material;
    s->root.mTransformation = (struct aiMatrix4x4){.a1 = 1, .b2 = 1, .c3 = 1, .d4 = 1};
    s->root.mNumMeshes = 1;
    s->root.mMeshes = s->root_meshes;
    s->scene = (struct aiScene){.mRootNode = &s->root,
                                .mNumMeshes = 1,
                                .mMeshes = s->mesh_list,
                                .mNumMaterials = 1,
                                .mMaterials = s->material_list};
    return s;
}

sb_status sb_assimp_write(const char* path, const char* format_id, const sb_mesh* mesh, const double* positions,
                          sb_error* err) {
    assimp_scene* s = assimp_scene_make(mesh, positions);
    if (!s) return sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory", path);
    enum aiReturn result = aiExportScene(&s->scene, format_id, path, 0);
    assimp_scene_free(s);
    if (result == aiReturn_SUCCESS) return SB_OK;
    remove(path);
    return sb_error_set(err, SB_ERR_IO, "%s: assimp's '%s' exporter failed", path, format_id);
}

/* ---- entry point ---------------------------------------------------------- */

sb_mesh_export_def sb_default_mesh_export_def(void) {
    return (sb_mesh_export_def){.positions = NULL, .up = {0.0, 0.0, 1.0}};
}

static sb_status write_text(const char* path, const export_format* format, const sb_mesh* mesh,
                            const sb_mesh_export_def* def, sb_error* err) {
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) return status;
    format->write_text(file.stream, mesh, def);
    return sb_atomic_commit(&file, err);
}

sb_status sb_mesh_export(const char* path, const char* format, const sb_mesh* mesh, const sb_mesh_export_def* def,
                         sb_error* err) {
    const export_format* f = format ? find_format(format) : NULL;
    if (!f)
        return sb_error_set(err, SB_ERR_INVALID, "%s: unknown export format '%s' (ply, obj, gltf, glb, irit or pov)",
                            path, format ? format : "(null)");
    sb_mesh_export_def options = def ? *def : sb_default_mesh_export_def();
    if (!options.positions) options.positions = mesh->positions;
    if (f->write_text) return write_text(path, f, mesh, &options, err);
    FILE* stream = fopen(path, "wb");
    if (!stream) return sb_error_set(err, SB_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    fclose(stream);
    return sb_assimp_write(path, f->assimp_id, mesh, options.positions, err);
}
