/* `factory: net`: a generated sheet as a net of bonds, Sekercioglu &
 * Duysak's net (a square net of bonds, no faces).
 *
 * A bond joins each two vertices next to each other along a row or a
 * column of the sheet; none runs across a cell's diagonal, and there are
 * no angle, stretch-bend or hinge terms, so the cells shear and the net
 * folds freely, as a net's meshes do. Each bond has the molecular
 * factory's edge terms (bond.k, spring.k, spring.damping,
 * bond.break_strain); the vertices and their masses are the molecular
 * factory's (mass each, or a third of each triangle's area times density).
 * The model has no triangles: frames still show the sheet's. */
#ifndef SB_NET_H
#define SB_NET_H

#include "scenes/scene.h"
#include "softbond/softbond.h"

/* Adds the net of the sheet MESH, made by the scene's mesh.nx x mesh.ny
 * (vertex row * nx + column, unreordered), to BUILDER. */
sb_status sb_scene_add_net(const sb_scene* scene, const sb_mesh* mesh, sb_builder* builder, sb_error* err);

#endif
