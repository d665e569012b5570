/* Frames ParaView opens: VTK XML UnstructuredGrid files (.vtu, ASCII), one
 * per frame, and a .pvd collection that lists them with their times. */
#ifndef SB_VTK_H
#define SB_VTK_H

#include "softbond/softbond.h"

/* One frame: the mesh's triangles as cells, per-point velocity, force and
 * the fixed flag. Arrays are 3n interleaved doubles. */
typedef struct sb_vtk_frame {
    const sb_mesh* mesh;
    const sb_model* model;
    const double* positions;
    const double* velocities;
    const double* forces;
} sb_vtk_frame;

/* "frame_000012.vtu": the name of frame `index` inside the output folder. */
void sb_vtk_frame_name(uint32_t index, char* out, size_t size);

sb_status sb_vtk_write_frame(const char* path, const sb_vtk_frame* frame, sb_error* err);
/* Lists frames 0 .. count-1 (named by sb_vtk_frame_name) at times[]. */
sb_status sb_vtk_write_collection(const char* path, const double* times, uint32_t count,
                                  sb_error* err);

#endif
