/* VTK XML output (see vtk.h): plain ASCII, Float64 data, triangles as
 * VTK_TRIANGLE (5) cells. Each file is written atomically. */
#include "scenes/vtk.h"
#include "scenes/atomic_file.h"

enum { VTK_TRIANGLE = 5 };

void sb_vtk_frame_name(uint32_t index, char* out, size_t size) {
    snprintf(out, size, "frame_%06u.vtu", index);
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
    for (uint32_t i = 0; i < n; i++)
        fprintf(f, "%s%d", i % 32 ? " " : "\n          ", sb_model_is_fixed(frame->model, i));
    fprintf(f, "\n        </DataArray>\n      </PointData>\n");
}

static void write_cells(FILE* f, const sb_mesh* mesh) {
    fprintf(f, "      <Cells>\n        <DataArray type=\"Int64\" Name=\"connectivity\" "
               "format=\"ascii\">\n");
    for (uint32_t t = 0; t < mesh->triangle_count; t++)
        fprintf(f, "          %u %u %u\n", mesh->triangles[3 * t], mesh->triangles[3 * t + 1],
                mesh->triangles[3 * t + 2]);
    fprintf(f, "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" "
               "format=\"ascii\">\n");
    for (uint32_t t = 0; t < mesh->triangle_count; t++)
        fprintf(f, "%s%u", t % 16 ? " " : "\n          ", 3 * (t + 1));
    fprintf(f, "\n        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" "
               "format=\"ascii\">\n");
    for (uint32_t t = 0; t < mesh->triangle_count; t++)
        fprintf(f, "%s%d", t % 32 ? " " : "\n          ", VTK_TRIANGLE);
    fprintf(f, "\n        </DataArray>\n      </Cells>\n");
}

static void write_grid(FILE* f, const sb_vtk_frame* frame) {
    fprintf(f,
            "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" "
            "byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
            "  <UnstructuredGrid>\n"
            "    <Piece NumberOfPoints=\"%u\" NumberOfCells=\"%u\">\n",
            frame->mesh->vertex_count, frame->mesh->triangle_count);
    write_point_data(f, frame);
    fprintf(f, "      <Points>\n");
    write_vectors(f, NULL, frame->positions, frame->mesh->vertex_count);
    fprintf(f, "      </Points>\n");
    write_cells(f, frame->mesh);
    fprintf(f, "    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
}

sb_status sb_vtk_write_frame(const char* path, const sb_vtk_frame* frame, sb_error* err) {
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) return status;
    write_grid(file.stream, frame);
    return sb_atomic_commit(&file, err);
}

sb_status sb_vtk_write_collection(const char* path, const double* times, uint32_t count,
                                  sb_error* err) {
    sb_atomic_file file;
    sb_status status = sb_atomic_open(&file, path, err);
    if (status != SB_OK) return status;
    fprintf(file.stream, "<?xml version=\"1.0\"?>\n"
                         "<VTKFile type=\"Collection\" version=\"0.1\" "
                         "byte_order=\"LittleEndian\">\n  <Collection>\n");
    for (uint32_t i = 0; i < count; i++) {
        char name[32];
        sb_vtk_frame_name(i, name, sizeof name);
        fprintf(file.stream,
                "    <DataSet timestep=\"%.17g\" group=\"\" part=\"0\" file=\"%s\"/>\n", times[i],
                name);
    }
    fprintf(file.stream, "  </Collection>\n</VTKFile>\n");
    return sb_atomic_commit(&file, err);
}
