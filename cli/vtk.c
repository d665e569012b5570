/* VTK XML output (see vtk.h): ASCII, or the arrays appended raw after the
 * XML (binary), or appended zlib-compressed (zlib), Float64 data, triangles as
 * VTK_TRIANGLE (5) cells, bonds as VTK_LINE (3) cells. Each file is written
 * atomically.
 *
 * The bonds go to a file of their own beside the surface, sharing its
 * points: ParaView merges the pieces of one .vtu into one grid and expects
 * every piece to carry the same arrays, so lines with strain and energy in
 * the surface's file would need made-up values for the triangles. Two files,
 * listed in the .pvd as parts 0 and 1 of each time step, open as a
 * multiblock dataset with clean arrays in each block. */
#define _POSIX_C_SOURCE 200809L
#include "cli/vtk.h"
#include "common/atomic_file.h"
#include "common/error.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <zlib.h>

enum { VTK_LINE = 3, VTK_TRIANGLE = 5, ZLIB_BLOCK = 1 << 15 };

void sb_vtk_frame_name(uint32_t index, const char* suffix, char* out, size_t size) {
    snprintf(out, size, "frame_%06u%s", index, suffix);
}

/* Where a file's arrays go: inline as text (ascii), or as an offset into
 * the appended block that follows the XML (binary, zlib). */
typedef struct vtk_out {
    FILE* f;
    sb_vtk_encoding encoding;
    unsigned char* data; /* the appended block so far */
    size_t size, capacity;
    bool failed; /* out of memory */
} vtk_out;

static void append(vtk_out* o, const void* bytes, size_t n) {
    if (o->failed) return;
    if (o->size + n > o->capacity) {
        size_t capacity = 2 * (o->size + n) + 4096;
        unsigned char* grown = realloc(o->data, capacity);
        if (!grown) {
            o->failed = true;
            return;
        }
        o->data = grown, o->capacity = capacity;
    }
    memcpy(o->data + o->size, bytes, n);
    o->size += n;
}

/* VTK's raw appended array: a UInt64 byte count, the bytes. Compressed
 * (vtkZLibDataCompressor): a header of UInt64s, the number of blocks, the
 * block size, the last block's size, each block's compressed size; then
 * the blocks, each zlib-compressed on its own. */
static void append_array(vtk_out* o, const void* bytes, size_t n) {
    if (o->encoding == SB_VTK_BINARY) {
        uint64_t count = n;
        append(o, &count, sizeof count);
        append(o, bytes, n);
        return;
    }
    uint64_t blocks = n ? (n + ZLIB_BLOCK - 1) / ZLIB_BLOCK : 0;
    uint64_t* header = malloc((3 + blocks) * sizeof *header);
    unsigned char* packed = malloc(compressBound(ZLIB_BLOCK) * (blocks ? blocks : 1));
    if (!header || !packed) {
        free(header), free(packed);
        o->failed = true;
        return;
    }
    header[0] = blocks, header[1] = ZLIB_BLOCK, header[2] = n % ZLIB_BLOCK ? n % ZLIB_BLOCK : (n ? ZLIB_BLOCK : 0);
    size_t at = 0;
    for (uint64_t b = 0; b < blocks; b++) {
        size_t from = (size_t)b * ZLIB_BLOCK, length = n - from < ZLIB_BLOCK ? n - from : ZLIB_BLOCK;
        uLongf packed_size = compressBound(ZLIB_BLOCK);
        if (compress2(packed + at, &packed_size, (const Bytef*)bytes + from, length, Z_DEFAULT_COMPRESSION) != Z_OK)
            o->failed = true;
        header[3 + b] = packed_size;
        at += packed_size;
    }
    append(o, header, (3 + blocks) * sizeof *header);
    append(o, packed, at);
    free(header), free(packed);
}

/* The DataArray's start tag; for the appended encodings a whole element
 * whose data is `bytes`. true: text follows (ascii), then array_end. */
static bool array_start(vtk_out* o, const char* type, const char* name, int components, const void* bytes, size_t n) {
    fprintf(o->f, "        <DataArray type=\"%s\"", type);
    if (name) fprintf(o->f, " Name=\"%s\"", name);
    if (components > 1) fprintf(o->f, " NumberOfComponents=\"%d\"", components);
    if (o->encoding == SB_VTK_ASCII) {
        fprintf(o->f, " format=\"ascii\">\n");
        return true;
    }
    fprintf(o->f, " format=\"appended\" offset=\"%zu\"/>\n", o->size);
    append_array(o, bytes, n);
    return false;
}

static void write_vectors(vtk_out* o, const char* name, const double* data, uint32_t n) {
    if (!array_start(o, "Float64", name, 3, data, 3 * (size_t)n * sizeof *data)) return;
    for (uint32_t i = 0; i < n; i++)
        fprintf(o->f, "          %.9g %.9g %.9g\n", data[3 * i], data[3 * i + 1], data[3 * i + 2]);
    fprintf(o->f, "        </DataArray>\n");
}

/* A whole array of small numbers: UInt8 or Int64, `per_line` to a line in text. */
static void write_integers(vtk_out* o, const char* type, const char* name, const int64_t* values, uint32_t n,
                           uint32_t per_line) {
    bool bytes = strcmp(type, "UInt8") == 0;
    size_t size = (size_t)n * (bytes ? 1 : sizeof *values);
    unsigned char* packed = bytes ? malloc(size + 1) : NULL;
    for (uint32_t i = 0; packed && i < n; i++) packed[i] = (unsigned char)values[i];
    if (bytes && !packed) {
        o->failed = true;
        return;
    }
    bool text = array_start(o, type, name, 1, bytes ? (const void*)packed : (const void*)values, size);
    free(packed);
    if (!text) return;
    for (uint32_t i = 0; i < n; i++) fprintf(o->f, "%s%lld", i % per_line ? " " : "\n          ", (long long)values[i]);
    fprintf(o->f, "\n        </DataArray>\n");
}

static void write_point_data(vtk_out* o, const sb_vtk_frame* frame) {
    uint32_t n = frame->mesh->vertex_count;
    fprintf(o->f, "      <PointData Vectors=\"velocity\">\n");
    write_vectors(o, "velocity", frame->velocities, n);
    write_vectors(o, "force", frame->forces, n);
    int64_t* fixed = malloc(((size_t)n + 1) * sizeof *fixed);
    if (!fixed) {
        o->failed = true;
        return;
    }
    for (uint32_t i = 0; i < n; i++) { /* a vertex a cut made has no model vertex: written free */
        uint32_t origin = frame->solver ? sb_solver_vertex_origin(frame->solver, i) : i;
        fixed[i] = origin < sb_model_vertex_count(frame->model) && sb_model_is_fixed(frame->model, origin);
    }
    write_integers(o, "UInt8", "fixed", fixed, n, 32);
    free(fixed);
    fprintf(o->f, "      </PointData>\n");
}

/* `count` cells of `corners` points each, their indices in `nodes`. */
static void write_cells(vtk_out* o, const uint32_t* nodes, uint32_t count, uint32_t corners, int type) {
    size_t n = (size_t)count * corners;
    int64_t* values = malloc((n + count + 1) * sizeof *values);
    if (!values) {
        o->failed = true;
        return;
    }
    fprintf(o->f, "      <Cells>\n");
    for (size_t k = 0; k < n; k++) values[k] = nodes[k];
    if (array_start(o, "Int64", "connectivity", 1, values, n * sizeof *values)) {
        for (uint32_t c = 0; c < count; c++) {
            fprintf(o->f, "         ");
            for (uint32_t k = 0; k < corners; k++) fprintf(o->f, " %u", nodes[corners * c + k]);
            fprintf(o->f, "\n");
        }
        fprintf(o->f, "        </DataArray>\n");
    }
    for (uint32_t c = 0; c < count; c++) values[c] = (int64_t)corners * (c + 1);
    write_integers(o, "Int64", "offsets", values, count, 16);
    for (uint32_t c = 0; c < count; c++) values[c] = type;
    write_integers(o, "UInt8", "types", values, count, 32);
    free(values);
    fprintf(o->f, "      </Cells>\n");
}

static void write_scalars(vtk_out* o, const char* name, const double* data, uint32_t n) {
    if (!array_start(o, "Float64", name, 1, data, (size_t)n * sizeof *data)) return;
    for (uint32_t i = 0; i < n; i++) fprintf(o->f, "%s%.9g", i % 8 ? " " : "\n          ", data[i]);
    fprintf(o->f, "\n        </DataArray>\n");
}

static void write_piece_start(vtk_out* o, const sb_vtk_frame* frame, uint32_t cells) {
    fprintf(o->f,
            "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
            "byte_order=\"LittleEndian\" header_type=\"UInt64\"%s>\n"
            "  <UnstructuredGrid>\n"
            "    <Piece NumberOfPoints=\"%u\" NumberOfCells=\"%u\">\n",
            o->encoding == SB_VTK_ZLIB ? " compressor=\"vtkZLibDataCompressor\"" : "", frame->mesh->vertex_count,
            cells);
}

static void write_points(vtk_out* o, const sb_vtk_frame* frame) {
    fprintf(o->f, "      <Points>\n");
    write_vectors(o, NULL, frame->positions, frame->mesh->vertex_count);
    fprintf(o->f, "      </Points>\n");
}

/* The end of the XML, then the appended block: "_" and the arrays' bytes. */
static void write_piece_end(vtk_out* o) {
    fprintf(o->f, "    </Piece>\n  </UnstructuredGrid>\n");
    if (o->encoding != SB_VTK_ASCII) {
        fprintf(o->f, "  <AppendedData encoding=\"raw\">\n   _");
        if (o->size) fwrite(o->data, 1, o->size, o->f); /* the commit checks the stream */
        fprintf(o->f, "\n  </AppendedData>\n");
    }
    fprintf(o->f, "</VTKFile>\n");
}

static void write_grid(vtk_out* o, const sb_vtk_frame* frame) {
    const sb_mesh* mesh = frame->mesh;
    write_piece_start(o, frame, mesh->triangle_count);
    write_point_data(o, frame);
    write_points(o, frame);
    write_cells(o, mesh->triangles, mesh->triangle_count, 3, VTK_TRIANGLE);
    write_piece_end(o);
}

/* Per unbroken bond: its two vertices, strain, energy and its index in the
 * model (see vtk.h); count of them. */
typedef struct bond_cells {
    uint32_t* nodes;
    double* strain;
    double* energy;
    double* index;
    uint32_t count;
} bond_cells;

static void bond_cells_free(bond_cells* b) {
    free(b->nodes);
    free(b->strain);
    free(b->energy);
    free(b->index);
}

static void measure_bond(const sb_vtk_frame* frame, uint32_t e, uint32_t c, bond_cells* b) {
    sb_bond_info bond = sb_model_bond(frame->model, e);
    uint32_t ends[2] = {bond.i, bond.j};
    if (frame->solver) sb_solver_bond(frame->solver, e, ends);
    bond.i = ends[0], bond.j = ends[1];
    const double* p = frame->positions + 3 * (size_t)bond.i;
    const double* q = frame->positions + 3 * (size_t)bond.j;
    double stretch = hypot(hypot(q[0] - p[0], q[1] - p[1]), q[2] - p[2]) - bond.rest_length;
    b->nodes[2 * c] = bond.i;
    b->nodes[2 * c + 1] = bond.j;
    b->strain[c] = bond.rest_length > 0.0 ? stretch / bond.rest_length : 0.0;
    b->energy[c] = 0.5 * (bond.k + bond.spring_k) * stretch * stretch;
    b->index[c] = (double)e;
}

/* Broken and severed bonds are left out: they carry no force and no
 * energy, so the cells' energies sum to log.csv's bond + spring terms. */
static bool bond_cells_make(const sb_vtk_frame* frame, uint32_t count, bond_cells* b) {
    size_t n = count ? count : 1;
    *b = (bond_cells){malloc(2 * n * sizeof *b->nodes), malloc(n * sizeof(double)), malloc(n * sizeof(double)),
                      malloc(n * sizeof(double)), 0};
    if (!b->nodes || !b->strain || !b->energy || !b->index) return false;
    for (uint32_t e = 0; e < count; e++)
        if (!frame->solver || !sb_solver_bond_broken(frame->solver, e)) measure_bond(frame, e, b->count++, b);
    return true;
}

static void write_bond_grid(vtk_out* o, const sb_vtk_frame* frame, const bond_cells* b) {
    write_piece_start(o, frame, b->count);
    fprintf(o->f, "      <CellData Scalars=\"strain\">\n");
    write_scalars(o, "strain", b->strain, b->count);
    write_scalars(o, "energy", b->energy, b->count);
    write_scalars(o, "bond", b->index, b->count);
    fprintf(o->f, "      </CellData>\n");
    write_points(o, frame);
    write_cells(o, b->nodes, b->count, 2, VTK_LINE);
    write_piece_end(o);
}

/* Commits the file, or (out of memory on the way) removes it. */
static sb_status finish(sb_atomic_file* file, vtk_out* o, const char* path, sb_error* err) {
    free(o->data);
    if (!o->failed) return sb_atomic_commit(file, err);
    sb_atomic_abort(file);
    return sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory (or zlib failed)", path);
}

sb_status sb_vtk_write_frame(const char* path, const sb_vtk_frame* frame, sb_error* err) {
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) return status;
    vtk_out o = {.f = file.stream, .encoding = frame->encoding};
    write_grid(&o, frame);
    return finish(&file, &o, path, err);
}

sb_status sb_vtk_write_bonds(const char* path, const sb_vtk_frame* frame, sb_error* err) {
    uint32_t count = sb_model_bond_count(frame->model);
    bond_cells bonds;
    sb_atomic_file file;
    sb_status status = bond_cells_make(frame, count, &bonds)
                           ? sb_atomic_open(&file, path, err)
                           : sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory", path);
    if (status == SB_OK) {
        vtk_out o = {.f = file.stream, .encoding = frame->encoding};
        write_bond_grid(&o, frame, &bonds);
        status = finish(&file, &o, path, err);
    }
    bond_cells_free(&bonds);
    return status;
}

static void write_dataset(FILE* f, double time, int part, const char* name) {
    fprintf(f, "    <DataSet timestep=\"%.17g\" group=\"\" part=\"%d\" file=\"%s\"/>\n", time, part, name);
}

sb_status sb_vtk_write_collection(const char* path, const double* times, uint32_t count, sb_error* err) {
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) return status;
    fprintf(file.stream, "<?xml version=\"1.0\"?>\n"
                         "<VTKFile type=\"Collection\" version=\"0.1\" "
                         "byte_order=\"LittleEndian\">\n  <Collection>\n");
    for (uint32_t i = 0; i < count; i++) {
        char name[32];
        sb_vtk_frame_name(i, ".vtu", name, sizeof name);
        write_dataset(file.stream, times[i], 0, name);
        sb_vtk_frame_name(i, "_bonds.vtu", name, sizeof name);
        write_dataset(file.stream, times[i], 1, name);
    }
    fprintf(file.stream, "  </Collection>\n</VTKFile>\n");
    return sb_atomic_commit(&file, err);
}
