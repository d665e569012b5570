/* Geometric pin selections (see pin.h). */
#include "scenes/pin.h"

#include <float.h>
#include <math.h>
#include <string.h>

typedef enum pin_kind {
    PIN_EDGE,    /* every vertex of the side */
    PIN_CORNERS, /* only the side's two end vertices */
    PIN_CLAMP    /* the side and its neighbours along the triangles */
} pin_kind;

typedef struct pin_rule {
    const char* name;
    int axis;    /* 0 = x, 1 = y: the side is where this coordinate is extreme */
    bool at_max; /* the max face (top, right) or the min face (bottom, left) */
    pin_kind kind;
} pin_rule;

static const pin_rule rules[] = {
    {"top_corners", 1, true, PIN_CORNERS},   {"bottom_corners", 1, false, PIN_CORNERS},
    {"left_corners", 0, false, PIN_CORNERS}, {"right_corners", 0, true, PIN_CORNERS},
    {"top_edge", 1, true, PIN_EDGE},         {"bottom_edge", 1, false, PIN_EDGE},
    {"left_edge", 0, false, PIN_EDGE},       {"right_edge", 0, true, PIN_EDGE},
    {"top_clamp", 1, true, PIN_CLAMP},       {"bottom_clamp", 1, false, PIN_CLAMP},
    {"left_clamp", 0, false, PIN_CLAMP},     {"right_clamp", 0, true, PIN_CLAMP},
};
enum { RULE_COUNT = sizeof rules / sizeof rules[0] };

static const pin_rule* find_rule(const char* name) {
    for (int i = 0; i < RULE_COUNT; i++)
        if (strcmp(rules[i].name, name) == 0) return &rules[i];
    return NULL;
}

bool sb_pin_known(const char* name) { return strcmp(name, "none") == 0 || find_rule(name) != NULL; }

const char* sb_pin_names(void) {
    return "none, top_corners, bottom_corners, left_corners, right_corners, top_edge, "
           "bottom_edge, left_edge, right_edge, top_clamp, bottom_clamp, left_clamp, right_clamp";
}

typedef struct box {
    double lo[3], hi[3];
} box;

static box bounding_box(const sb_mesh* mesh) {
    box b = {{DBL_MAX, DBL_MAX, DBL_MAX}, {-DBL_MAX, -DBL_MAX, -DBL_MAX}};
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        for (int a = 0; a < 3; a++) {
            b.lo[a] = fmin(b.lo[a], mesh->positions[3 * v + a]);
            b.hi[a] = fmax(b.hi[a], mesh->positions[3 * v + a]);
        }
    }
    return b;
}

static double box_tolerance(const box* b) {
    double size = 0.0;
    for (int a = 0; a < 3; a++) size = fmax(size, b->hi[a] - b->lo[a]);
    return 1e-9 * (size > 0.0 ? size : 1.0);
}

static bool on_side(const pin_rule* rule, const box* b, double tol, const double* p) {
    double face = rule->at_max ? b->hi[rule->axis] : b->lo[rule->axis];
    return fabs(p[rule->axis] - face) <= tol;
}

static void pin(sb_builder* builder, uint32_t v) { sb_builder_vertex(builder, v)->fixed = true; }

static void pin_corners(const pin_rule* rule, const sb_mesh* mesh, const box* b, double tol, sb_builder* builder) {
    int along = 1 - rule->axis;
    int64_t first = -1, last = -1;
    for (uint32_t v = 0; v < mesh->vertex_count; v++) {
        const double* p = &mesh->positions[3 * v];
        if (!on_side(rule, b, tol, p)) continue;
        if (first < 0 || p[along] < mesh->positions[3 * first + along]) first = v;
        if (last < 0 || p[along] > mesh->positions[3 * last + along]) last = v;
    }
    if (first >= 0) pin(builder, (uint32_t)first);
    if (last >= 0) pin(builder, (uint32_t)last);
}

/* Every vertex of a triangle that touches the side: on a triangle mesh,
 * the side's vertices and their neighbours. */
static void pin_clamp(const pin_rule* rule, const sb_mesh* mesh, const box* b, double tol, sb_builder* builder) {
    for (uint32_t t = 0; t < mesh->triangle_count; t++) {
        const uint32_t* tri = &mesh->triangles[3 * t];
        bool touches = false;
        for (int c = 0; c < 3; c++) touches |= on_side(rule, b, tol, &mesh->positions[3 * tri[c]]);
        if (touches)
            for (int c = 0; c < 3; c++) pin(builder, tri[c]);
    }
}

void sb_pin_apply(const char* name, const sb_mesh* mesh, sb_builder* builder) {
    const pin_rule* rule = find_rule(name);
    if (!rule || mesh->vertex_count == 0) return;
    box b = bounding_box(mesh);
    double tol = box_tolerance(&b);
    if (rule->kind == PIN_CORNERS) {
        pin_corners(rule, mesh, &b, tol, builder);
        return;
    }
    for (uint32_t v = 0; v < mesh->vertex_count; v++)
        if (on_side(rule, &b, tol, &mesh->positions[3 * v])) pin(builder, v);
    if (rule->kind == PIN_CLAMP) pin_clamp(rule, mesh, &b, tol, builder);
}
