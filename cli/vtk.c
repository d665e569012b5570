/* VTK XML output (see vtk.h): plain ASCII, Float64 data, triangles as
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

enum { VTK_LINE = 3, VTK_TRIANGLE = 5 };

void sb_vtk_frame_name(uint32_t index, const char* suffix, char* out, size_t size) {
    snprintf(out, size, "frame_%06u%s", index, suffix);
}

static void write_vectors(FILE* f, const char* name, const double* data, uint32_t n) {
    fprintf(f,
            "        <DataArray type=\"Float64\"%s%s%s NumberOfComponents=\"3\" "
            "format=\"ascii\">\n",
            name ? " Name=\"" : "", name ? name : "", name ? "\"" : "");
    for (uint32_t i = 0; i < n; i++)
        fprintf(f, "          %.9g %.9g %.9g\n", data[3 * i], data[3 * i + 1], data[3 * i + 2]);
    fprintf(f, "        </DataArray>\n");
}

static void write_point_data(FILE* f, const sb_vtk_frame* frame) {
    uint32_t n = frame->mesh->vertex_count;
    fprintf(f, "      <PointData Vectors=\"velocity\">\n");
    write_vectors(f, "velocity", frame->velocities, n);
    write_vectors(f, "force", frame->forces, n);
    fprintf(f, "        <DataArray type=\"UInt8\" Name=\"fixed\" format=\"ascii\">\n");
    for (uint32_t i = 0; i < n; i++) {
        uint32_t origin = frame->solver ? sb_solver_vertex_origin(frame->solver, i) : i;
        fprintf(f, "%s%d", i % 32 ? " " : "\n          ", sb_model_is_fixed(frame->model, origin));
    }
    fprintf(f, "\n        </DataArray>\n      </PointData>\n");
}

/* `count` cells of `corners` points each, their indices in `nodes`. */
static void write_cells(FILE* f, const uint32_t* nodes, uint32_t count, uint32_t corners, int type) {
    fprintf(f, "      <Cells>\n        <DataArray type=\"Int64\" Name=\"connectivity\" "
               "format=\"ascii\">\n");
    for (uint32_t c = 0; c < count; c++) {
        fprintf(f, "         ");
        for (uint32_t k = 0; k < corners; k++) fprintf(f, " %u", nodes[corners * c + k]);
        fprintf(f, "\n");
    }
    fprintf(f, "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" "
               "format=\"ascii\">\n");
    for (uint32_t c = 0; c < count; c++) fprintf(f, "%s%u", c % 16 ? " " : "\n          ", corners * (c + 1));
    fprintf(f, "\n        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" "
               "format=\"ascii\">\n");
    for (uint32_t c = 0; c < count; c++) fprintf(f, "%s%d", c % 32 ? " " : "\n          ", type);
    fprintf(f, "\n        </DataArray>\n      </Cells>\n");
}

static void write_scalars(FILE* f, const char* name, const double* data, uint32_t n) {
    fprintf(f, "        <DataArray type=\"Float64\" Name=\"%s\" format=\"ascii\">\n", name);
    for (uint32_t i = 0; i < n; i++) fprintf(f, "%s%.9g", i % 8 ? " " : "\n          ", data[i]);
    fprintf(f, "\n        </DataArray>\n");
}

static void write_piece_start(FILE* f, const sb_vtk_frame* frame, uint32_t cells) {
    fprintf(f,
            "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
            "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
            "  <UnstructuredGrid>\n"
            "    <Piece NumberOfPoints=\"%u\" NumberOfCells=\"%u\">\n",
            frame->mesh->vertex_count, cells);
}

static void write_points(FILE* f, const sb_vtk_frame* frame) {
    fprintf(f, "      <Points>\n");
    write_vectors(f, NULL, frame->positions, frame->mesh->vertex_count);
    fprintf(f, "      </Points>\n");
}

static void write_piece_end(FILE* f) { fprintf(f, "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n"); }

static void write_grid(FILE* f, const sb_vtk_frame* frame) {
    const sb_mesh* mesh = frame->mesh;
    write_piece_start(f, frame, mesh->triangle_count);
    write_point_data(f, frame);
    write_points(f, frame);
    write_cells(f, mesh->triangles, mesh->triangle_count, 3, VTK_TRIANGLE);
    write_piece_end(f);
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

static void write_bond_grid(FILE* f, const sb_vtk_frame* frame, const bond_cells* b) {
    write_piece_start(f, frame, b->count);
    fprintf(f, "      <CellData Scalars=\"strain\">\n");
    write_scalars(f, "strain", b->strain, b->count);
    write_scalars(f, "energy", b->energy, b->count);
    write_scalars(f, "bond", b->index, b->count);
    fprintf(f, "      </CellData>\n");
    write_points(f, frame);
    write_cells(f, b->nodes, b->count, 2, VTK_LINE);
    write_piece_end(f);
}

sb_status sb_vtk_write_frame(const char* path, const sb_vtk_frame* frame, sb_error* err) {
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) return status;
    write_grid(file.stream, frame);
    return sb_atomic_commit(&file, err);
}

sb_status sb_vtk_write_bonds(const char* path, const sb_vtk_frame* frame, sb_error* err) {
    uint32_t count = sb_model_bond_count(frame->model);
    bond_cells bonds;
    sb_atomic_file file;
    sb_status status = bond_cells_make(frame, count, &bonds)
                           ? sb_atomic_open(&file, path, err)
                           : sb_error_set(err, SB_ERR_NOMEM, "%s: out of memory", path);
    if (status == SB_OK) {
        write_bond_grid(file.stream, frame, &bonds);
        status = sb_atomic_commit(&file, err);
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
