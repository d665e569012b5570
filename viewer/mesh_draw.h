/* Drawing the bodies from a snapshot: vertices (points), edges (the
 * model's bonds: dark lines, or coloured by strain), faces (lit, plain or
 * textured). The surface is the compiled model's triangles: a surface torn
 * by vertex splitting is not drawn as torn yet (no topology accessor). */
#ifndef SB_VIEWER_MESH_DRAW_H
#define SB_VIEWER_MESH_DRAW_H

#include "viewer/shaders.h"

typedef struct sb_draw_flags {
    bool vertices, edges, strain, faces, texture;
} sb_draw_flags;

typedef struct sb_mesh_draw {
    uint32_t vertex_count, edge_count, triangle_count;
    uint32_t* edges; /* 2 per bond */
    float* rest;     /* rest length per bond, m */
    float* positions;
    float* normals;
    float* strain_vertices; /* per bond 2 × (x y z r g b a) */
    uint32_t* triangles;    /* 3 per triangle */
    double strain_scale;    /* the colour scale's end: the largest |strain| of the last frame */
    GLuint vao, positions_vbo, normals_vbo, uv_vbo, triangles_ebo, edges_ebo;
    GLuint strain_vao, strain_vbo, texture;
} sb_mesh_draw;

sb_status sb_mesh_draw_create(sb_mesh_draw* d, const sb_model* model, sb_error* err);
void sb_mesh_draw_free(sb_mesh_draw* d);
/* Takes a snapshot's positions (3n); with strain, the strain colours too. */
void sb_mesh_draw_update(sb_mesh_draw* d, const sb_real* positions, bool strain);
void sb_mesh_draw_render(const sb_mesh_draw* d, const sb_shaders* s, const float matrix[16], const float light[3],
                         sb_draw_flags flags);
/* The colour of a strain on the scale [−scale, scale]: blue, white, red. */
void sb_strain_color(double strain, double scale, float rgba[4]);

#endif
