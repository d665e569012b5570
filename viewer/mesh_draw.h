/* Drawing the bodies from a snapshot: vertices (points), edges (the
 * unbroken bonds: dark lines, or coloured by strain), faces (the live
 * triangles, lit, plain or textured), with the topology the simulation
 * thread last handed over (viewer/topology.h), so a torn surface is drawn
 * torn as it changes. */
#ifndef SB_VIEWER_MESH_DRAW_H
#define SB_VIEWER_MESH_DRAW_H

#include "viewer/shaders.h"
#include "viewer/topology.h"

typedef struct sb_draw_flags {
    bool vertices, edges, strain, faces, texture;
} sb_draw_flags;

typedef struct sb_mesh_draw {
    uint32_t capacity;       /* vertices there is room for */
    uint32_t vertex_count;   /* of the last snapshot */
    uint32_t triangle_count; /* of the topology */
    uint32_t edge_count;
    const sb_view_topology* topology; /* the last given (its arrays are read while drawing) */
    float* rest;                      /* rest length per bond of the model, m */
    float* model_uv;                  /* 2 per model vertex: the texture's coordinates */
    uint32_t model_vertices;          /* in model_uv */
    float* uv;                        /* 2 per vertex: its origin's */
    float* positions;
    float* normals;
    float* strain_vertices; /* per edge 2 × (x y z r g b a) */
    double strain_scale;    /* the colour scale's end: the last frame's 98th percentile of |strain| */
    GLuint vao, positions_vbo, normals_vbo, uv_vbo, triangles_ebo, edges_ebo;
    GLuint strain_vao, strain_vbo, texture;
} sb_mesh_draw;

/* Room for capacity vertices of model (and the copies tearing makes). */
sb_status sb_mesh_draw_create(sb_mesh_draw* d, const sb_model* model, uint32_t capacity, sb_error* err);
void sb_mesh_draw_free(sb_mesh_draw* d);
/* The triangles and edges to draw from now on (t must stay valid). */
void sb_mesh_draw_topology(sb_mesh_draw* d, const sb_view_topology* t);
/* Takes a snapshot's positions (3 per vertex, count vertices); with strain, the strain colours too. */
void sb_mesh_draw_update(sb_mesh_draw* d, const sb_real* positions, uint32_t count, bool strain);
void sb_mesh_draw_render(const sb_mesh_draw* d, const sb_shaders* s, const float matrix[16], const float light[3],
                         sb_draw_flags flags);
/* The colour of a strain on the scale [−scale, scale]: blue, white, red. */
void sb_strain_color(double strain, double scale, float rgba[4]);

#endif
