// A POV-Ray scene for softbond's POV reader tests, written by hand after
// the Spring Systems film maker's examples: a fixed floor, a free
// tetrahedron with every local, and a bare mesh2 with none.
#include "colors.inc"
camera { location <0, -6, 3> look_at <0, 0, 0> }
light_source { <2, -4, 6> color rgb <1, 1, 1> }
plane { z, -1 pigment { color rgb <0.4, 0.4, 0.4> } }

#declare Floor = mesh2
{
    #local spring_system_fixed = true;
    vertex_vectors { 4, <-2, -2, 0>, <2, -2, 0>, <2, 2, 0>, <-2, 2, 0> }
    face_indices { 2, <0, 1, 2>, <0, 2, 3> }
    texture { pigment { color rgb <0.2, 0.6, 0.2> } }
}

#declare Ball = mesh2
{
    #local spring_system_ks = 600;
    #local spring_system_kb = 500;
    #local spring_system_ds = 2;
    #local spring_system_db = 1.5;
    #local spring_system_mass = 3;
    #local spring_system_vicinity = 0.1;
    #local spring_system_fixed = false;
    vertex_vectors {
        4,
        <0, 0, 1>, <1, 0, 1>, <0, 1, 1>, <0, 0, 2>
    }
    normal_vectors { 1, <0, 0, 1> }
    /* the texture indices after a face are skipped */
    face_indices {
        4,
        <0, 2, 1>, 0, <0, 1, 3>, 0, <0, 3, 2>, 0, <1, 2, 3>, 0
    }
    texture_list { 1, texture { pigment { color rgb <1, 0, 0> } } }
}

object { Floor }
object { Ball }
object {
    mesh2 {
        vertex_vectors { 3, <5, 0, 0>, <6, 0, 0>, <5, 1, 0> }
        face_indices { 1, <0, 1, 2> }
    }
    translate <0, 0, 1>
}
