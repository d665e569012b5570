/* The benchmark's table of cases, shared by sb_bench and the LAMMPS
 * exporter so that both time exactly the same mesh, constants and time step.
 *
 * Every case is built the same way: a generated mesh, the molecular-mechanics
 * terms (bond stretch, angle bend, stretch-bend) with constants scaled by the
 * mean rest edge length h so that every resolution is equally stiff and
 * equally stable, a uniform vertex mass (areal density × area / vertices),
 * gravity, Verlet, and a time step from the stiffest vertex's frequency. */
#ifndef SB_BENCH_CASES_H
#define SB_BENCH_CASES_H

#include "softbond/softbond.h"

typedef enum sb_bench_shape { SB_BENCH_SHEET, SB_BENCH_ICOSPHERE } sb_bench_shape;

/* The generator's numbering, a Morton renumbering (sb_mesh_reorder), or a
 * random one (the worst case an imported file could bring). */
typedef enum sb_bench_order { SB_BENCH_GENERATED, SB_BENCH_MORTON, SB_BENCH_SHUFFLED } sb_bench_order;

typedef struct sb_bench_case {
    const char* name; /* e.g. "sheet_100k" */
    sb_bench_shape shape;
    uint32_t size;        /* sheet: nx = ny; icosphere: subdivisions */
    bool small;           /* part of --cases small */
    sb_bench_order order; /* vertex and triangle numbering */
} sb_bench_case;

/* The constants every case shares. */
typedef struct sb_bench_options {
    bool all_terms; /* add the damped spring and the hinge bend */
    double jitter;  /* sheet jitter, a fraction of the spacing */
} sb_bench_options;

/* A built case: its mesh, material, model and step. */
typedef struct sb_bench_setup {
    sb_mesh mesh;
    sb_material_def material;
    double edge_length; /* mean rest edge length h, m */
    double dt;          /* s */
    uint32_t pins[2];
    uint32_t pin_count;
    sb_model* model;
} sb_bench_setup;

extern const sb_bench_case sb_bench_cases[];
extern const size_t sb_bench_case_count;

#define SB_BENCH_DEFAULT_JITTER 0.1
#define SB_BENCH_GRAVITY 9.81 /* m/s², along −z */

/* Finds a case by name, or NULL. */
const sb_bench_case* sb_bench_find_case(const char* name);

/* Generates the mesh and chooses material and dt; model stays NULL. */
sb_status sb_bench_prepare(const sb_bench_case* c, const sb_bench_options* o, sb_bench_setup* s, sb_error* err);
/* Prepares, then builds and compiles the model (with the pins). */
sb_status sb_bench_build(const sb_bench_case* c, const sb_bench_options* o, sb_bench_setup* s, sb_error* err);
void sb_bench_setup_free(sb_bench_setup* s);

#endif
