/* Frames ParaView opens: VTK XML UnstructuredGrid files (.vtu: ASCII, binary or zlib), two
 * per frame (the surface and the bonds), and a .pvd collection that lists
 * them with their times, the surface as part 0 and the bonds as part 1. */
#ifndef SB_VTK_H
#define SB_VTK_H

#include "softbond/softbond.h"

/* How a .vtu holds its arrays (the scene's output.vtu): as text inside
 * the XML, or appended after it as raw little-endian bytes (each array a
 * UInt64 byte count and its bytes), or appended zlib-compressed
 * (compressor vtkZLibDataCompressor: 32 KiB blocks, each compressed on its
 * own). ParaView, VTK and meshio read all three. */
typedef enum sb_vtk_encoding { SB_VTK_ASCII, SB_VTK_BINARY, SB_VTK_ZLIB } sb_vtk_encoding;

/* One frame: the mesh's triangles as cells, per-point velocity, force and
 * the fixed flag. Arrays are 3n interleaved doubles. With a solver, the
 * points are its vertices now (a tearing solver's copies included: each
 * has its origin's fixed flag) and the bonds its current ends. */
typedef struct sb_vtk_frame {
    const sb_mesh* mesh;
    const sb_model* model;
    const double* positions;
    const double* velocities;
    const double* forces;
    const sb_solver* solver; /* or NULL: the model's numbering */
    sb_vtk_encoding encoding; /* 0: ascii */
} sb_vtk_frame;

/* "frame_000012" and suffix: the name of a file of frame `index` inside the
 * output folder ("frame_000012.vtu", the bonds "frame_000012_bonds.vtu",
 * and the other formats' "frame_000012.pov", ...). */
void sb_vtk_frame_name(uint32_t index, const char* suffix, char* out, size_t size);

sb_status sb_vtk_write_frame(const char* path, const sb_vtk_frame* frame, sb_error* err);
/* The model's bonds as VTK_LINE cells over the frame's points, with cell
 * data `strain` = (l - l0) / l0, `energy` = ½ (k + spring_k) (l - l0)²,
 * J: the bond's share of the bond-stretch (Eq. 3) and spring (Eq. 2)
 * energies, and `bond`, its index in the model. With a solver, the bonds
 * it has broken (by strain or by a blade) are left out, so the energies sum
 * to log.csv's bond + spring of the same frame. */
sb_status sb_vtk_write_bonds(const char* path, const sb_vtk_frame* frame, sb_error* err);
/* Lists frames 0 .. count-1 at times[]: each one's surface (part 0, .vtu)
 * and bonds (part 1, _bonds.vtu). */
sb_status sb_vtk_write_collection(const char* path, const double* times, uint32_t count, sb_error* err);

#endif
