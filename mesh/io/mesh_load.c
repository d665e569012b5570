/* sb_mesh_load: reads a triangle mesh from a file.
 *
 * Dispatch is on the extension, case-insensitively: ".obj" and ".off" go to
 * softbond's own readers (obj_reader.c, off_reader.c), which keep the file's
 * vertex order and count exactly; ".node", ".ele" and ".msh" are tetrahedral
 * meshes (tet_readers.c) whose boundary surface is returned; ".itd" and
 * ".irit" are IRIT text data (irit_reader.c) and ".pov" POV-Ray mesh2
 * objects (pov_reader.c); every other extension goes through assimp.
 *
 * The assimp path:
 *   - post-processing: Triangulate, JoinIdenticalVertices, SortByPType,
 *     DropNormals (so that per-face normals, as in STL, do not keep corners
 *     apart), FindInvalidData and ValidateDataStructure; not FindDegenerates,
 *     which would turn degenerate triangles into lines and points that could
 *     no longer be told from the file's own: softbond finds them itself;
 *   - the node hierarchy is walked depth-first from the root and each node's
 *     meshes are placed with the node's accumulated transform (a mesh used by
 *     two nodes is imported twice); if no node references a mesh, every mesh
 *     is taken as is;
 *   - merged (the default): all meshes become one and vertices with
 *     bitwise-identical positions (after the transform) are joined, across
 *     meshes too, so that a seam in texture coordinates or a split between
 *     meshes never tears the body; separate (sb_mesh_load_def): each placed
 *     mesh becomes its own object, joined within itself only, and a mesh with
 *     no triangle left gives no object; vertex order is the order of first
 *     appearance in assimp's output;
 *   - only triangles are kept (points and lines are ignored and counted) and
 *     a degenerate triangle is dropped and counted: one whose corners join
 *     into fewer than three vertices, or whose area is zero to rounding,
 *     |(b - a) x (c - a)| <= 1e-12 * (longest edge)^2 (collinear corners);
 *   - assimp is a large third-party parser that crashes, aborts, hangs or
 *     allocates without bound on some hostile files, so it never runs in
 *     the caller's process: a PLY file's header is checked first
 *     (ply_check.c), then the import and the merge above run in a child
 *     process (isolate.c) with a time limit of ASSIMP_SECONDS plus one
 *     second per MiB of file and ASSIMP_MEMORY plus ASSIMP_MEMORY_PER_BYTE
 *     bytes per byte of file, and send the meshes back through a pipe; a
 *     child that dies or runs out of time becomes "FILE: the importer
 *     failed (killed by signal 11, Segmentation fault)". Nothing in the
 *     caller's process touches assimp's state, so imports may run from
 *     several threads at once.
 * Assimp reads positions in single precision: a file's coordinates come back
 * rounded to float. */
#define _POSIX_C_SOURCE 200809L

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "common/error.h"
#include "mesh/io/isolate.h"
#include "mesh/io/mesh_readers.h"
#include "softbond/pov.h"
#include "softbond/volume.h"

/* ---- growable mesh arrays ------------------------------------------------ */

static bool grow(void** data, size_t* capacity, size_t needed, size_t element_size) {
    if (needed <= *capacity) {
        return true;
    }
    size_t capacity_new = *capacity < 64 ? 64 : *capacity;
    while (capacity_new < needed) {
        if (capacity_new > SIZE_MAX / 2) {
            return false;
        }
        capacity_new *= 2;
    }
    if (capacity_new > SIZE_MAX / element_size) {
        return false;
    }
    void* grown = realloc(*data, capacity_new * element_size);
    if (grown == NULL) {
        return false;
    }
    *data = grown;
    *capacity = capacity_new;
    return true;
}

bool sb_mesh_builder_add_vertex(sb_mesh_builder* b, double x, double y, double z) {
    if (b->vertex_count >= UINT32_MAX ||
        !grow((void**)&b->positions, &b->vertex_capacity, b->vertex_count + 1, 3 * sizeof(double))) {
        return false;
    }
    double* p = b->positions + 3 * b->vertex_count++;
    p[0] = x;
    p[1] = y;
    p[2] = z;
    return true;
}

bool sb_mesh_builder_add_triangle(sb_mesh_builder* b, uint32_t i, uint32_t j, uint32_t k) {
    if (b->triangle_count >= UINT32_MAX ||
        !grow((void**)&b->triangles, &b->triangle_capacity, b->triangle_count + 1, 3 * sizeof(uint32_t))) {
        return false;
    }
    uint32_t* t = b->triangles + 3 * b->triangle_count++;
    t[0] = i;
    t[1] = j;
    t[2] = k;
    return true;
}

void sb_mesh_builder_finish(sb_mesh_builder* b, sb_mesh* out) {
    /* Shrink to fit; a failed shrink keeps the larger block. */
    if (b->vertex_count > 0 && b->vertex_count < b->vertex_capacity) {
        double* p = realloc(b->positions, b->vertex_count * 3 * sizeof(double));
        if (p != NULL) {
            b->positions = p;
        }
    }
    if (b->triangle_count > 0 && b->triangle_count < b->triangle_capacity) {
        uint32_t* t = realloc(b->triangles, b->triangle_count * 3 * sizeof(uint32_t));
        if (t != NULL) {
            b->triangles = t;
        }
    }
    out->vertex_count = (uint32_t)b->vertex_count;
    out->positions = b->positions;
    out->triangle_count = (uint32_t)b->triangle_count;
    out->triangles = b->triangles;
    memset(b, 0, sizeof *b);
}

void sb_mesh_builder_free(sb_mesh_builder* b) {
    free(b->positions);
    free(b->triangles);
    memset(b, 0, sizeof *b);
}

/* ---- text ---------------------------------------------------------------- */

static bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f' || c == '\0'; }

bool sb_text_next_token(sb_text_line* line, const char** token, size_t* length) {
    while (line->p < line->end && is_blank(*line->p)) {
        line->p++;
    }
    if (line->p >= line->end) {
        return false;
    }
    const char* start = line->p;
    while (line->p < line->end && !is_blank(*line->p)) {
        line->p++;
    }
    *token = start;
    *length = (size_t)(line->p - start);
    return true;
}

bool sb_text_parse_double(const char* token, size_t length, double* out) {
    char buffer[128];
    if (length == 0 || length >= sizeof buffer) {
        return false;
    }
    memcpy(buffer, token, length);
    buffer[length] = '\0';
    /* strtod would skip leading blanks; tokens have none, but be strict. */
    if (isspace((unsigned char)buffer[0])) {
        return false;
    }
    char* end = NULL;
    errno = 0;
    double value = strtod(buffer, &end);
    if (end != buffer + length) {
        return false;
    }
    /* Overflow gives ±HUGE_VAL (non-finite: reported by the reader);
     * underflow to a tiny or zero value is accepted. */
    *out = value;
    return true;
}

bool sb_text_parse_integer(const char* token, size_t length, long long* out) {
    size_t i = 0;
    bool negative = false;
    if (i < length && (token[i] == '+' || token[i] == '-')) {
        negative = token[i] == '-';
        i++;
    }
    if (i == length) {
        return false;
    }
    long long value = 0;
    for (; i < length; i++) {
        if (token[i] < '0' || token[i] > '9') {
            return false;
        }
        if (value > (INT64_MAX - 9) / 10) {
            return false;
        }
        value = value * 10 + (token[i] - '0');
    }
    *out = negative ? -value : value;
    return true;
}

/* ---- reading a file ------------------------------------------------------ */

sb_status sb_read_whole_file(const char* path, char** text, size_t* size, sb_error* err) {
    FILE* file = fopen(path, "rb");
    if (file == NULL) {
        return sb_error_at(err, SB_ERR_IO, path, 0, "cannot open: %s", strerror(errno));
    }
    char* data = NULL;
    size_t used = 0, capacity = 0;
    /* One allocation when the size is known (a regular file), else grow. */
    struct stat info;
    if (fstat(fileno(file), &info) == 0 && S_ISREG(info.st_mode) && info.st_size > 0 &&
        (uintmax_t)info.st_size < SIZE_MAX - 65536 - 1) {
        capacity = (size_t)info.st_size + 65536 + 1;
        data = malloc(capacity);
        if (data == NULL) {
            capacity = 0;
        }
    }
    for (;;) {
        if (!grow((void**)&data, &capacity, used + 65536 + 1, 1)) {
            free(data);
            fclose(file);
            return sb_error_at(err, SB_ERR_NOMEM, path, 0, "out of memory reading the file");
        }
        size_t got = fread(data + used, 1, capacity - used - 1, file);
        used += got;
        if (got == 0) {
            break;
        }
    }
    if (ferror(file)) {
        int code = errno;
        free(data);
        fclose(file);
        return sb_error_at(err, SB_ERR_IO, path, 0, "cannot read: %s", strerror(code));
    }
    fclose(file);
    data[used] = '\0';
    *text = data;
    *size = used;
    return SB_OK;
}

/* ---- assimp -------------------------------------------------------------- */

static uint64_t hash_position(const double p[3]) {
    uint64_t h = 0x9e3779b97f4a7c15u;
    for (int c = 0; c < 3; c++) {
        uint64_t bits;
        memcpy(&bits, &p[c], sizeof bits);
        h ^= bits + 0x9e3779b97f4a7c15u + (h << 6) + (h >> 2);
        h *= 0xff51afd7ed558ccdu;
        h ^= h >> 33;
    }
    return h;
}

/* A 4x4 affine transform in double, row-major: p' = M (p, 1). */
typedef struct transform4 {
    double m[16];
} transform4;

typedef struct assimp_merge {
    const char* path;
    const struct aiScene* scene;
    sb_mesh_builder mesh;
    sb_weld_table weld;
    uint32_t* remap; /* per mesh: assimp vertex -> output vertex */
    size_t remap_capacity;
    bool any_node_mesh;
    bool separate;    /* one object per placed mesh */
    sb_mesh* objects; /* separate: the finished objects */
    size_t object_count, object_capacity;
    size_t empty_vertices; /* separate: vertices of meshes with no triangle */
    sb_mesh_load_report* report;
} assimp_merge;

static void transform_point(const transform4* t, const struct aiVector3D* v, double out[3]) {
    const double* m = t->m;
    double x = v->x, y = v->y, z = v->z;
    out[0] = m[0] * x + m[1] * y + m[2] * z + m[3];
    out[1] = m[4] * x + m[5] * y + m[6] * z + m[7];
    out[2] = m[8] * x + m[9] * y + m[10] * z + m[11];
    double w = m[12] * x + m[13] * y + m[14] * z + m[15];
    if (w != 1.0 && w != 0.0) {
        out[0] /= w;
        out[1] /= w;
        out[2] /= w;
    }
}

static void transform_compose(const transform4* parent, const struct aiMatrix4x4* local, transform4* out) {
    const ai_real* l = &local->a1; /* a1..d4 are contiguous, row-major */
    for (int i = 0; i < 4; i++) {
        for (int j = 0; j < 4; j++) {
            double s = 0.0;
            for (int k = 0; k < 4; k++) {
                s += parent->m[4 * i + k] * (double)l[4 * k + j];
            }
            out->m[4 * i + j] = s;
        }
    }
}

static void weld_insert(sb_weld_table* weld, const double* positions, uint32_t index) {
    size_t mask = weld->capacity - 1;
    size_t slot = (size_t)hash_position(positions + 3 * (size_t)index) & mask;
    while (weld->slots[slot] != 0) {
        slot = (slot + 1) & mask;
    }
    weld->slots[slot] = index + 1;
}

static bool weld_reserve(sb_weld_table* weld, const sb_mesh_builder* mesh, size_t count) {
    if (count <= weld->capacity / 2) {
        return true;
    }
    size_t capacity = weld->capacity < 1024 ? 1024 : weld->capacity;
    while (count > capacity / 2) {
        if (capacity > SIZE_MAX / 2 / sizeof(uint32_t)) {
            return false;
        }
        capacity *= 2;
    }
    uint32_t* slots = calloc(capacity, sizeof(uint32_t));
    if (slots == NULL) {
        return false;
    }
    free(weld->slots);
    weld->slots = slots;
    weld->capacity = capacity;
    for (size_t v = 0; v < mesh->vertex_count; v++) {
        weld_insert(weld, mesh->positions, (uint32_t)v);
    }
    return true;
}

bool sb_mesh_builder_weld_vertex(sb_mesh_builder* mesh, sb_weld_table* weld, const double p[3], uint32_t* index) {
    double q[3] = {p[0] + 0.0, p[1] + 0.0, p[2] + 0.0}; /* -0 joins +0 */
    if (!weld_reserve(weld, mesh, mesh->vertex_count + 1)) {
        return false;
    }
    size_t mask = weld->capacity - 1;
    size_t slot = (size_t)hash_position(q) & mask;
    for (uint32_t entry; (entry = weld->slots[slot]) != 0; slot = (slot + 1) & mask) {
        const double* e = mesh->positions + 3 * (size_t)(entry - 1);
        if (e[0] == q[0] && e[1] == q[1] && e[2] == q[2]) {
            *index = entry - 1;
            return true;
        }
    }
    if (!sb_mesh_builder_add_vertex(mesh, q[0], q[1], q[2])) {
        return false;
    }
    *index = (uint32_t)(mesh->vertex_count - 1);
    weld->slots[slot] = *index + 1;
    return true;
}

/* Two corners joined, or the corners collinear to rounding. */
static bool degenerate(const double* positions, const uint32_t t[3]) {
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
        return true;
    }
    const double* a = positions + 3 * (size_t)t[0];
    const double* b = positions + 3 * (size_t)t[1];
    const double* c = positions + 3 * (size_t)t[2];
    double u[3], v[3], w[3], n[3];
    for (int k = 0; k < 3; k++) {
        u[k] = b[k] - a[k];
        v[k] = c[k] - a[k];
        w[k] = c[k] - b[k];
    }
    n[0] = u[1] * v[2] - u[2] * v[1];
    n[1] = u[2] * v[0] - u[0] * v[2];
    n[2] = u[0] * v[1] - u[1] * v[0];
    double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2];
    double vv = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    double ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
    double longest = fmax(uu, fmax(vv, ww));
    double area2 = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    return area2 <= 1e-24 * longest * longest;
}

/* Separate objects: the mesh built so far becomes an object and the next
 * one starts empty, with an empty join table. */
static bool flush_object(assimp_merge* merge) {
    if (merge->mesh.triangle_count == 0) {
        merge->empty_vertices += merge->mesh.vertex_count;
        sb_mesh_builder_free(&merge->mesh);
    } else {
        if (!grow((void**)&merge->objects, &merge->object_capacity, merge->object_count + 1, sizeof(sb_mesh))) {
            return false;
        }
        sb_mesh_builder_finish(&merge->mesh, &merge->objects[merge->object_count++]);
    }
    if (merge->weld.slots != NULL) {
        memset(merge->weld.slots, 0, merge->weld.capacity * sizeof(uint32_t));
    }
    return true;
}

static sb_status merge_mesh_into(assimp_merge* merge, const struct aiMesh* mesh, const transform4* transform,
                                 unsigned mesh_index, sb_error* err);

static sb_status merge_mesh(assimp_merge* merge, const struct aiMesh* mesh, const transform4* transform,
                            unsigned mesh_index, sb_error* err) {
    merge->report->source_meshes++;
    sb_status status = merge_mesh_into(merge, mesh, transform, mesh_index, err);
    if (status == SB_OK && merge->separate && !flush_object(merge)) {
        status = sb_error_at(err, SB_ERR_NOMEM, merge->path, 0, "out of memory");
    }
    return status;
}

static sb_status merge_mesh_into(assimp_merge* merge, const struct aiMesh* mesh, const transform4* transform,
                                 unsigned mesh_index, sb_error* err) {
    if (mesh->mNumVertices == 0 || mesh->mVertices == NULL) {
        return SB_OK;
    }
    if (!grow((void**)&merge->remap, &merge->remap_capacity, mesh->mNumVertices, sizeof(uint32_t))) {
        return sb_error_at(err, SB_ERR_NOMEM, merge->path, 0, "out of memory");
    }
    for (unsigned v = 0; v < mesh->mNumVertices; v++) {
        double p[3];
        transform_point(transform, &mesh->mVertices[v], p);
        if (!isfinite(p[0]) || !isfinite(p[1]) || !isfinite(p[2])) {
            return sb_error_at(err, SB_ERR_PARSE, merge->path, 0, "non-finite position at vertex %u of mesh %u", v,
                               mesh_index);
        }
        if (!sb_mesh_builder_weld_vertex(&merge->mesh, &merge->weld, p, &merge->remap[v])) {
            return sb_error_at(err, SB_ERR_NOMEM, merge->path, 0, "out of memory or more than 2^32-1 vertices");
        }
    }
    for (unsigned f = 0; f < mesh->mNumFaces && mesh->mFaces != NULL; f++) {
        const struct aiFace* face = &mesh->mFaces[f];
        if (face->mNumIndices != 3 || face->mIndices == NULL) {
            merge->report->ignored_primitives++; /* points and lines */
            continue;
        }
        uint32_t t[3];
        for (int c = 0; c < 3; c++) {
            unsigned index = face->mIndices[c];
            if (index >= mesh->mNumVertices) {
                return sb_error_at(err, SB_ERR_PARSE, merge->path, 0, "face %u of mesh %u uses vertex %u of %u", f,
                                   mesh_index, index, mesh->mNumVertices);
            }
            t[c] = merge->remap[index];
        }
        if (degenerate(merge->mesh.positions, t)) {
            merge->report->degenerate_faces++;
            continue;
        }
        if (!sb_mesh_builder_add_triangle(&merge->mesh, t[0], t[1], t[2])) {
            return sb_error_at(err, SB_ERR_NOMEM, merge->path, 0, "out of memory or more than 2^32-1 triangles");
        }
    }
    return SB_OK;
}

enum { MAX_NODE_DEPTH = 256 };

static sb_status merge_node(assimp_merge* merge, const struct aiNode* node, const transform4* parent, int depth,
                            sb_error* err) {
    if (depth > MAX_NODE_DEPTH) {
        return sb_error_at(err, SB_ERR_PARSE, merge->path, 0, "node hierarchy deeper than %d", MAX_NODE_DEPTH);
    }
    transform4 transform;
    transform_compose(parent, &node->mTransformation, &transform);
    for (unsigned i = 0; i < node->mNumMeshes && node->mMeshes != NULL; i++) {
        unsigned m = node->mMeshes[i];
        if (m >= merge->scene->mNumMeshes || merge->scene->mMeshes[m] == NULL) {
            continue;
        }
        merge->any_node_mesh = true;
        sb_status status = merge_mesh(merge, merge->scene->mMeshes[m], &transform, m, err);
        if (status != SB_OK) {
            return status;
        }
    }
    for (unsigned i = 0; i < node->mNumChildren && node->mChildren != NULL; i++) {
        if (node->mChildren[i] != NULL) {
            sb_status status = merge_node(merge, node->mChildren[i], &transform, depth + 1, err);
            if (status != SB_OK) {
                return status;
            }
        }
    }
    return SB_OK;
}

static sb_status merge_scene(assimp_merge* merge, sb_error* err) {
    const struct aiScene* scene = merge->scene;
    transform4 identity = {{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}};
    sb_status status = SB_OK;
    if (scene->mRootNode != NULL) {
        status = merge_node(merge, scene->mRootNode, &identity, 0, err);
    }
    for (unsigned m = 0; status == SB_OK && !merge->any_node_mesh && m < scene->mNumMeshes && scene->mMeshes != NULL;
         m++) {
        if (scene->mMeshes[m] != NULL) {
            status = merge_mesh(merge, scene->mMeshes[m], &identity, m, err);
        }
    }
    if (status == SB_OK && merge->mesh.triangle_count == 0 && merge->object_count == 0) {
        status = sb_error_at(err, SB_ERR_PARSE, merge->path, 0,
                             "no triangles (%zu vertices, %u degenerate triangles "
                             "dropped, %u points and lines)",
                             merge->mesh.vertex_count + merge->empty_vertices, merge->report->degenerate_faces,
                             merge->report->ignored_primitives);
    }
    return status;
}

static void objects_free(sb_mesh* objects, size_t count) {
    for (size_t i = 0; i < count; i++) {
        sb_mesh_free(&objects[i]);
    }
    free(objects);
}

/* The import and the merge: what runs in the child. */
static sb_status import_assimp(const char* path, bool separate, sb_mesh** objects, uint32_t* object_count,
                               sb_mesh_load_report* report, sb_error* err) {
    const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_SortByPType |
                           aiProcess_DropNormals | aiProcess_FindInvalidData | aiProcess_ValidateDataStructure;
    const struct aiScene* scene = aiImportFile(path, flags);
    if (scene == NULL) {
        const char* why = aiGetErrorString();
        return sb_error_at(err, SB_ERR_PARSE, path, 0, "%s",
                           why != NULL && why[0] != '\0' ? why : "assimp cannot read it");
    }
    assimp_merge merge = {.path = path, .scene = scene, .separate = separate, .report = report};
    sb_status status = SB_OK;
    if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) {
        status = sb_error_at(err, SB_ERR_PARSE, path, 0, "incomplete scene (no meshes)");
    } else {
        status = merge_scene(&merge, err);
    }
    aiReleaseImport(scene);
    free(merge.weld.slots);
    free(merge.remap);
    if (status == SB_OK && !separate) {
        merge.objects = malloc(sizeof(sb_mesh));
        if (merge.objects == NULL) {
            status = sb_error_at(err, SB_ERR_NOMEM, path, 0, "out of memory");
        } else {
            sb_mesh_builder_finish(&merge.mesh, &merge.objects[0]);
            merge.object_count = 1;
        }
    }
    sb_mesh_builder_free(&merge.mesh);
    if (status != SB_OK) {
        objects_free(merge.objects, merge.object_count);
        return status;
    }
    *objects = merge.objects;
    *object_count = (uint32_t)merge.object_count;
    return SB_OK;
}

/* ---- the import in a child process ------------------------------------------- */

enum { ASSIMP_SECONDS = 30, ASSIMP_MEMORY_PER_BYTE = 200 };
#define ASSIMP_MEMORY ((size_t)1 << 30)

/* The child's answer: this header, then per object its two counts, its
 * positions and its triangles. */
typedef struct import_answer {
    int32_t status;
    uint32_t source_meshes, degenerate_faces, ignored_primitives, object_count;
    sb_error err;
} import_answer;

typedef struct import_job {
    const char* path;
    bool separate;
} import_job;

static bool blob_append(sb_blob* blob, size_t* capacity, const void* data, size_t size) {
    if (size == 0) {
        return true;
    }
    if (!grow((void**)&blob->data, capacity, blob->size + size, 1)) {
        return false;
    }
    memcpy(blob->data + blob->size, data, size);
    blob->size += size;
    return true;
}

static bool encode_objects(sb_blob* blob, size_t* capacity, const sb_mesh* objects, uint32_t count) {
    bool ok = true;
    for (uint32_t i = 0; i < count && ok; i++) {
        const sb_mesh* m = &objects[i];
        uint32_t counts[2] = {m->vertex_count, m->triangle_count};
        ok = blob_append(blob, capacity, counts, sizeof counts) &&
             blob_append(blob, capacity, m->positions, 3 * (size_t)m->vertex_count * sizeof(double)) &&
             blob_append(blob, capacity, m->triangles, 3 * (size_t)m->triangle_count * sizeof(uint32_t));
    }
    return ok;
}

/* Runs in the child (sb_isolated_fn). */
static void import_in_child(void* arg, sb_blob* blob) {
    const import_job* job = arg;
    sb_mesh_load_report report = {0};
    sb_mesh* objects = NULL;
    uint32_t count = 0;
    import_answer answer = {0};
    answer.status = import_assimp(job->path, job->separate, &objects, &count, &report, &answer.err);
    answer.source_meshes = report.source_meshes;
    answer.degenerate_faces = report.degenerate_faces;
    answer.ignored_primitives = report.ignored_primitives;
    answer.object_count = count;
    size_t capacity = 0;
    if (!blob_append(blob, &capacity, &answer, sizeof answer) || !encode_objects(blob, &capacity, objects, count)) {
        free(blob->data);
        *blob = (sb_blob){0}; /* no whole answer: the parent says so */
    }
    objects_free(objects, count);
}

/* Takes size bytes from the answer at *at; false when it is too short. */
static bool take(const sb_blob* blob, size_t* at, void* out, size_t size) {
    if (size > blob->size - *at) {
        return false;
    }
    memcpy(out, blob->data + *at, size);
    *at += size;
    return true;
}

static bool decode_object(const sb_blob* blob, size_t* at, sb_mesh* m) {
    uint32_t counts[2];
    if (!take(blob, at, counts, sizeof counts)) {
        return false;
    }
    size_t positions = 3 * (size_t)counts[0] * sizeof(double), triangles = 3 * (size_t)counts[1] * sizeof(uint32_t);
    if (positions + triangles > blob->size - *at) {
        return false;
    }
    m->positions = malloc(positions ? positions : 1);
    m->triangles = malloc(triangles ? triangles : 1);
    m->vertex_count = counts[0];
    m->triangle_count = counts[1];
    return m->positions != NULL && m->triangles != NULL && take(blob, at, m->positions, positions) &&
           take(blob, at, m->triangles, triangles);
}

static sb_status decode_answer(const char* path, const sb_blob* blob, sb_mesh** objects, uint32_t* object_count,
                               sb_mesh_load_report* report, sb_error* err) {
    import_answer answer;
    size_t at = 0;
    if (!take(blob, &at, &answer, sizeof answer)) {
        return sb_error_at(err, SB_ERR_IO, path, 0, "the importer failed (a short answer)");
    }
    report->source_meshes = answer.source_meshes;
    report->degenerate_faces = answer.degenerate_faces;
    report->ignored_primitives = answer.ignored_primitives;
    if (answer.status != SB_OK) {
        answer.err.message[sizeof answer.err.message - 1] = '\0';
        return sb_error_set(err, (sb_status)answer.status, "%s", answer.err.message);
    }
    sb_mesh* meshes = calloc(answer.object_count ? answer.object_count : 1, sizeof *meshes);
    bool ok = meshes != NULL;
    for (uint32_t i = 0; i < answer.object_count && ok; i++) {
        ok = decode_object(blob, &at, &meshes[i]);
    }
    if (!ok) {
        objects_free(meshes, meshes ? answer.object_count : 0);
        return sb_error_at(err, SB_ERR_NOMEM, path, 0, "out of memory or a short answer from the importer");
    }
    *objects = meshes;
    *object_count = answer.object_count;
    return SB_OK;
}

static sb_status load_assimp(const char* path, bool separate, sb_mesh** objects, uint32_t* object_count,
                             sb_mesh_load_report* report, sb_error* err) {
    /* Open it ourselves first, for the same missing-file message as the
     * readers (assimp would only say it could not open it). */
    FILE* file = fopen(path, "rb");
    if (file == NULL) {
        return sb_error_at(err, SB_ERR_IO, path, 0, "cannot open: %s", strerror(errno));
    }
    struct stat info;
    bool sized = fstat(fileno(file), &info) == 0;
    fclose(file);
    if (sb_path_has_extension(path, ".ply")) {
        sb_status status = sb_ply_check(path, err);
        if (status != SB_OK) {
            return status;
        }
    }
    double size = sized ? (double)info.st_size : 0.0;
    sb_isolate_limits limits = {ASSIMP_SECONDS + size / (1 << 20),
                                ASSIMP_MEMORY + (size_t)fmin(size * ASSIMP_MEMORY_PER_BYTE, (double)(SIZE_MAX / 4))};
    import_job job = {path, separate};
    sb_blob blob;
    char why[160];
    if (sb_isolate_run(import_in_child, &job, &limits, &blob, why, sizeof why) != SB_OK) {
        return sb_error_at(err, SB_ERR_PARSE, path, 0, "the importer failed (%s)", why);
    }
    sb_status status = decode_answer(path, &blob, objects, object_count, report, err);
    free(blob.data);
    return status;
}

/* ---- tetrahedral meshes: their boundary ---------------------------------- */

static sb_status load_volume_surface(const char* path, sb_mesh* out, sb_error* err) {
    sb_tet_mesh volume;
    sb_status status = sb_tet_mesh_load(path, &volume, err);
    if (status == SB_OK) {
        status = sb_tet_mesh_surface(&volume, out, err);
    }
    sb_tet_mesh_free(&volume);
    return status;
}

/* ---- dispatch ------------------------------------------------------------ */

bool sb_path_has_extension(const char* path, const char* extension) {
    const char* slash = strrchr(path, '/');
    const char* name = slash != NULL ? slash + 1 : path;
    const char* dot = strrchr(name, '.');
    if (dot == NULL) {
        return false;
    }
    for (size_t i = 0;; i++) {
        if (tolower((unsigned char)dot[i]) != extension[i]) {
            return false;
        }
        if (extension[i] == '\0') {
            return true;
        }
    }
}

sb_mesh_load_def sb_default_mesh_load_def(void) { return (sb_mesh_load_def){.separate_objects = false}; }

void sb_mesh_objects_free(sb_mesh* objects, uint32_t count) { objects_free(objects, count); }

/* The formats read by softbond's own readers or as a tetrahedral mesh: one
 * object, nothing dropped. */
static sb_status load_single(const char* path, bool obj, sb_mesh* out, sb_error* err) {
    if (sb_tet_mesh_path(path)) {
        return load_volume_surface(path, out, err);
    }
    char* text = NULL;
    size_t size = 0;
    sb_status status = sb_read_whole_file(path, &text, &size, err);
    if (status != SB_OK) {
        return status;
    }
    status = obj ? sb_obj_parse(path, text, size, out, err) : sb_off_parse(path, text, size, out, err);
    free(text);
    if (status != SB_OK) {
        memset(out, 0, sizeof *out);
    }
    return status;
}

sb_status sb_mesh_load_ex(const char* path, const sb_mesh_load_def* def, sb_mesh** objects, uint32_t* object_count,
                          sb_mesh_load_report* report, sb_error* err) {
    sb_mesh_load_report scratch;
    report = report != NULL ? report : &scratch;
    memset(report, 0, sizeof *report);
    if (objects == NULL || object_count == NULL) {
        return sb_error_set(err, SB_ERR_INVALID, "sb_mesh_load_ex: no output objects");
    }
    *objects = NULL;
    *object_count = 0;
    if (path == NULL || path[0] == '\0') {
        return sb_error_set(err, SB_ERR_INVALID, "sb_mesh_load_ex: empty path");
    }
    struct stat info;
    if (stat(path, &info) == 0 && S_ISDIR(info.st_mode)) {
        return sb_error_at(err, SB_ERR_IO, path, 0, "is a directory");
    }
    sb_mesh_load_def defaults = sb_default_mesh_load_def();
    def = def != NULL ? def : &defaults;
    if (sb_path_has_extension(path, ".itd") || sb_path_has_extension(path, ".irit")) {
        report->reader = "irit";
        sb_status status =
            sb_irit_load(path, def->separate_objects, objects, object_count, &report->degenerate_faces, err);
        report->source_meshes = report->object_count = *object_count;
        return status;
    }
    if (sb_pov_path(path)) {
        report->reader = "pov";
        sb_status status = sb_pov_load_meshes(path, def->separate_objects, objects, object_count, err);
        report->source_meshes = report->object_count = *object_count;
        return status;
    }
    bool obj = sb_path_has_extension(path, ".obj");
    bool own = sb_tet_mesh_path(path) || sb_path_has_extension(path, ".off") || (obj && !def->separate_objects);
    if (obj && !own) {
        /* assimp's OBJ reader is lenient: softbond's strict reader checks
         * the file first, for the same errors as a merged load. */
        sb_mesh check;
        sb_status status = load_single(path, true, &check, err);
        sb_mesh_free(&check);
        if (status != SB_OK) {
            return status;
        }
    }
    if (!own) {
        report->reader = "assimp";
        sb_status status = load_assimp(path, def->separate_objects, objects, object_count, report, err);
        report->object_count = *object_count;
        return status;
    }
    report->reader = sb_tet_mesh_path(path) ? "tetrahedral" : obj ? "obj" : "off";
    sb_mesh* one = calloc(1, sizeof *one);
    if (one == NULL) {
        return sb_error_at(err, SB_ERR_NOMEM, path, 0, "out of memory");
    }
    sb_status status = load_single(path, obj, one, err);
    if (status != SB_OK) {
        free(one);
        return status;
    }
    report->source_meshes = 1;
    report->object_count = 1;
    *objects = one;
    *object_count = 1;
    return SB_OK;
}

sb_status sb_mesh_load(const char* path, sb_mesh* out, sb_error* err) {
    if (out == NULL) {
        return sb_error_set(err, SB_ERR_INVALID, "sb_mesh_load: no output mesh");
    }
    memset(out, 0, sizeof *out);
    if (path == NULL || path[0] == '\0') {
        return sb_error_set(err, SB_ERR_INVALID, "sb_mesh_load: empty path");
    }
    sb_mesh* objects = NULL;
    uint32_t count = 0;
    sb_status status = sb_mesh_load_ex(path, NULL, &objects, &count, NULL, err);
    if (status == SB_OK) {
        *out = objects[0];
        free(objects);
    }
    return status;
}
