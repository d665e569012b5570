/* softbond.Model: a compiled, immutable model, made from NumPy arrays
 * (vertices, bonds, triangles, tetrahedra), from a triangle mesh by the
 * molecular factory (arrays, a file or a generator), or from a tetrahedral
 * mesh by the tissue factories (Young's modulus). Each constructor fills an
 * sb_builder and compiles it; the library's validation names the first bad
 * element. */
#include "sbpy.h"

#include <math.h>

PyObject* sbpy_model_wrap(sb_model* model, PyObject* owner) {
    SbpyModel* self = PyObject_New(SbpyModel, &SbpyModelType);
    if (!self) {
        if (!owner) sb_model_destroy(model);
        return NULL;
    }
    self->model = model;
    self->owner = owner;
    Py_XINCREF(owner);
    return (PyObject*)self;
}

static void model_dealloc(SbpyModel* self) {
    if (self->owner)
        Py_DECREF(self->owner);
    else
        sb_model_destroy(self->model);
    PyObject_Free(self);
}

/** Compiles the builder into a new Model (the builder is destroyed). */
static PyObject* compile(sb_builder* builder) {
    sb_error err = {{0}};
    sb_model* model = sb_builder_compile(builder, &err);
    sb_builder_destroy(builder);
    if (!model) return sbpy_raise(SB_ERR_INVALID, err.message);
    return sbpy_model_wrap(model, NULL);
}

/** Pins the vertices `fixed` names: indices, or a boolean mask of every vertex. */
static int pin(sb_builder* builder, PyObject* fixed, const char* function) {
    if (!fixed || fixed == Py_None) return 0;
    uint32_t n = sb_builder_vertex_count(builder);
    PyArrayObject* probe = (PyArrayObject*)PyArray_FROMANY(fixed, NPY_NOTYPE, 0, 0, 0);
    if (probe && PyArray_ISBOOL(probe)) {
        PyArrayObject* mask = sbpy_array(fixed, function, "fixed", NPY_BOOL, 0);
        Py_DECREF(probe);
        if (!mask) return -1;
        if (PyArray_DIM(mask, 0) != (npy_intp)n) {
            PyErr_Format(PyExc_ValueError, "%s: 'fixed' as a mask must have %u entries, got %zd", function, n,
                         (Py_ssize_t)PyArray_DIM(mask, 0));
            Py_DECREF(mask);
            return -1;
        }
        const npy_bool* m = PyArray_DATA(mask);
        for (uint32_t v = 0; v < n; v++)
            if (m[v]) sb_builder_vertex(builder, v)->fixed = true;
        Py_DECREF(mask);
        return 0;
    }
    Py_XDECREF(probe);
    PyErr_Clear();
    PyArrayObject* indices = sbpy_index_array(fixed, function, "fixed", 0);
    if (!indices) return -1;
    const int64_t* v = PyArray_DATA(indices);
    for (npy_intp k = 0; k < PyArray_DIM(indices, 0); k++) {
        if (v[k] >= n) {
            PyErr_Format(PyExc_ValueError, "%s: 'fixed' names vertex %lld of %u", function, (long long)v[k], n);
            Py_DECREF(indices);
            return -1;
        }
        sb_builder_vertex(builder, (uint32_t)v[k])->fixed = true;
    }
    Py_DECREF(indices);
    return 0;
}

/* ---- from arrays ---- */

/** The per-element constants of one kind of element, read from kwargs. */
typedef struct constants {
    PyArrayObject* owners[8];
    const double* values[8];
    double scalars[8];
} constants;

static double constant(const constants* c, int which, npy_intp element) {
    return c->values[which] ? c->values[which][element] : c->scalars[which];
}

static void constants_release(constants* c) {
    for (int i = 0; i < 8; i++) Py_CLEAR(c->owners[i]);
}

static int constants_read(constants* c, const char* function, PyObject* const* objects, const char* const* names,
                          const double* fallbacks, int count, npy_intp elements) {
    memset(c, 0, sizeof *c);
    for (int i = 0; i < count; i++)
        if (sbpy_per_element(objects[i], function, names[i], elements, fallbacks[i], &c->owners[i], &c->values[i],
                             &c->scalars[i]) < 0) {
            constants_release(c);
            return -1;
        }
    return 0;
}

static int add_vertices(sb_builder* builder, PyObject* vertices, PyObject* masses, PyObject* velocities,
                        const char* function) {
    PyArrayObject* x = sbpy_array(vertices, function, "vertices", NPY_DOUBLE, 3);
    if (!x) return -1;
    npy_intp n = PyArray_DIM(x, 0);
    PyArrayObject* v =
        velocities && velocities != Py_None ? sbpy_array(velocities, function, "velocities", NPY_DOUBLE, 3) : NULL;
    constants m;
    PyObject* objects[] = {masses};
    const char* names[] = {"masses"};
    double fallback[] = {1.0};
    int status = -1;
    if ((velocities && velocities != Py_None && !v) || constants_read(&m, function, objects, names, fallback, 1, n) < 0)
        goto done;
    if (v && PyArray_DIM(v, 0) != n) {
        PyErr_Format(PyExc_ValueError, "%s: 'velocities' must have as many rows as 'vertices'", function);
        constants_release(&m);
        goto done;
    }
    const double* xp = PyArray_DATA(x);
    for (npy_intp i = 0; i < n; i++) {
        sb_vertex_def def = sb_default_vertex_def();
        memcpy(def.position, xp + 3 * i, sizeof def.position);
        if (v) memcpy(def.velocity, (const double*)PyArray_DATA(v) + 3 * i, sizeof def.velocity);
        def.mass = constant(&m, 0, i);
        if (sb_builder_add_vertex(builder, &def) < 0) {
            PyErr_NoMemory();
            constants_release(&m);
            goto done;
        }
    }
    constants_release(&m);
    status = 0;
done:
    Py_DECREF(x);
    Py_XDECREF(v);
    return status;
}

/** One kind of element from_arrays takes: its index array's name and width,
 * its per-element constants (names and fallbacks) and how one is added. */
typedef struct element_kind {
    const char* name;
    int width;
    int constant_count;
    const char* const* constant_names;
    const double* fallbacks;
    int (*add)(sb_builder* builder, const int64_t* v, const constants* c, npy_intp element);
} element_kind;

static int add_elements(sb_builder* builder, PyObject* elements, PyObject* const* k, const element_kind* kind,
                        const char* function) {
    if (!elements || elements == Py_None) return 0;
    PyArrayObject* indices = sbpy_index_array(elements, function, kind->name, kind->width);
    if (!indices) return -1;
    npy_intp n = PyArray_DIM(indices, 0);
    constants c;
    if (constants_read(&c, function, k, kind->constant_names, kind->fallbacks, kind->constant_count, n) < 0) {
        Py_DECREF(indices);
        return -1;
    }
    const int64_t* v = PyArray_DATA(indices);
    int status = 0;
    for (npy_intp e = 0; e < n && status == 0; e++)
        if (kind->add(builder, v + kind->width * e, &c, e) < 0) status = -1, PyErr_NoMemory();
    constants_release(&c);
    Py_DECREF(indices);
    return status;
}

static int add_bond(sb_builder* builder, const int64_t* v, const constants* c, npy_intp b) {
    sb_bond_def def = sb_default_bond_def();
    def.i = (uint32_t)v[0];
    def.j = (uint32_t)v[1];
    def.k = constant(c, 0, b);
    def.spring_k = constant(c, 1, b);
    def.spring_damping = constant(c, 2, b);
    def.rest_length = constant(c, 3, b);
    def.break_min = constant(c, 4, b);
    def.break_max = constant(c, 5, b);
    return sb_builder_add_bond(builder, &def);
}

static int add_triangle(sb_builder* builder, const int64_t* v, const constants* c, npy_intp t) {
    sb_triangle_def def = {(uint32_t)v[0], (uint32_t)v[1], (uint32_t)v[2], constant(c, 0, t), constant(c, 1, t)};
    return sb_builder_add_triangle(builder, &def);
}

static int add_tet(sb_builder* builder, const int64_t* v, const constants* c, npy_intp t) {
    sb_tet_def def = {.v = {(uint32_t)v[0], (uint32_t)v[1], (uint32_t)v[2], (uint32_t)v[3]},
                      .young_modulus = constant(c, 0, t),
                      .poisson_ratio = constant(c, 1, t)}; /* undamped: β through from_tets */
    return sb_builder_add_tet(builder, &def);
}

static int add_hinge(sb_builder* builder, const int64_t* v, const constants* c, npy_intp h) {
    sb_hinge_def def = {(uint32_t)v[0], (uint32_t)v[1], (uint32_t)v[2], (uint32_t)v[3], constant(c, 0, h)};
    return sb_builder_add_hinge(builder, &def);
}

static const element_kind bond_kind = {
    "bonds",
    2,
    6,
    (const char* const[]){"bond_k", "spring_k", "spring_damping", "rest_lengths", "break_min", "break_max"},
    (const double[]){0, 0, 0, -1, 0, INFINITY},
    add_bond};
static const element_kind triangle_kind = {
    "triangles", 3, 2, (const char* const[]){"angle_k", "stretch_bend_k"}, (const double[]){0, 0}, add_triangle};
static const element_kind tet_kind = {
    "tetrahedra", 4, 2, (const char* const[]){"young_modulus", "poisson_ratio"}, (const double[]){0, 0.3}, add_tet};
static const element_kind hinge_kind = {"hinges", 4, 1, (const char* const[]){"bend_k"}, (const double[]){0},
                                        add_hinge};

static PyObject* model_from_arrays(PyObject* cls, PyObject* args, PyObject* kwargs) {
    (void)cls;
    static const char* function = "Model.from_arrays()";
    static char* keywords[] = {"vertices",      "masses",        "velocities",     "fixed",          "bonds",
                               "bond_k",        "spring_k",      "spring_damping", "rest_lengths",   "break_min",
                               "break_max",     "triangles",     "angle_k",        "stretch_bend_k", "tetrahedra",
                               "young_modulus", "poisson_ratio", "hinges",         "bend_k",         NULL};
    PyObject *vertices, *masses = NULL, *velocities = NULL, *fixed = NULL, *bonds = NULL, *triangles = NULL,
                        *tets = NULL, *hinges = NULL;
    PyObject* bond_k[6] = {NULL};
    PyObject* hinge_k[1] = {NULL};
    PyObject* tri_k[2] = {NULL};
    PyObject* tet_k[2] = {NULL};
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O|$OOOOOOOOOOOOOOOOOO:from_arrays", keywords, &vertices, &masses,
                                     &velocities, &fixed, &bonds, &bond_k[0], &bond_k[1], &bond_k[2], &bond_k[3],
                                     &bond_k[4], &bond_k[5], &triangles, &tri_k[0], &tri_k[1], &tets, &tet_k[0],
                                     &tet_k[1], &hinges, &hinge_k[0]))
        return NULL;
    sb_builder* builder = sb_builder_create();
    if (!builder) return PyErr_NoMemory();
    if (add_vertices(builder, vertices, masses, velocities, function) < 0 || pin(builder, fixed, function) < 0 ||
        add_elements(builder, bonds, bond_k, &bond_kind, function) < 0 ||
        add_elements(builder, triangles, tri_k, &triangle_kind, function) < 0 ||
        add_elements(builder, tets, tet_k, &tet_kind, function) < 0 ||
        add_elements(builder, hinges, hinge_k, &hinge_kind, function) < 0) {
        sb_builder_destroy(builder);
        return NULL;
    }
    return compile(builder);
}

/* ---- from a triangle mesh: the molecular factory ---- */

/** The material keywords (sb_material_def) and `fixed`, for every mesh constructor. */
typedef struct mesh_options {
    sb_material_def material;
    PyObject* fixed;
} mesh_options;

#define MESH_OPTION_COUNT 10
static void mesh_option_table(mesh_options* o, sbpy_option* table) {
    o->material = sb_default_material_def();
    o->fixed = NULL;
    sbpy_option entries[MESH_OPTION_COUNT] = {
        {"bond_k", SBPY_DOUBLE, &o->material.bond_k, NULL},
        {"angle_k", SBPY_DOUBLE, &o->material.angle_k, NULL},
        {"stretch_bend_k", SBPY_DOUBLE, &o->material.stretch_bend_k, NULL},
        {"spring_k", SBPY_DOUBLE, &o->material.spring_k, NULL},
        {"spring_damping", SBPY_DOUBLE, &o->material.spring_damping, NULL},
        {"bend_k", SBPY_DOUBLE, &o->material.bend_k, NULL},
        {"mass", SBPY_DOUBLE, &o->material.mass, NULL},
        {"density", SBPY_DOUBLE, &o->material.density, NULL},
        {"break_strain", SBPY_DOUBLE, &o->material.break_strain, NULL},
        {"fixed", SBPY_OBJECT, &o->fixed, NULL},
    };
    memcpy(table, entries, sizeof entries);
}

/** The model of mesh by the molecular factory with options' material; frees the mesh. */
static PyObject* model_of_mesh(sb_mesh* mesh, const mesh_options* options, const char* function) {
    sb_builder* builder = sb_builder_create();
    if (!builder) {
        sb_mesh_free(mesh);
        return PyErr_NoMemory();
    }
    sb_error err = {{0}};
    sb_status status = sb_builder_add_mesh(builder, mesh, &options->material, &err);
    sb_mesh_free(mesh);
    if (status != SB_OK) {
        sb_builder_destroy(builder);
        return sbpy_raise(status, err.message);
    }
    if (pin(builder, options->fixed, function) < 0) {
        sb_builder_destroy(builder);
        return NULL;
    }
    return compile(builder);
}

/** Splits kwargs into the table's (read) and the mesh options (read too). */
static int read_mesh_kwargs(const char* function, PyObject* kwargs, const sbpy_option* own, size_t own_count,
                            mesh_options* options) {
    sbpy_option table[MESH_OPTION_COUNT + 8];
    mesh_option_table(options, table);
    memcpy(table + MESH_OPTION_COUNT, own, own_count * sizeof *own);
    return sbpy_options(function, kwargs, table, MESH_OPTION_COUNT + own_count);
}

/** A library mesh (malloc'd, sb_mesh_free) from (n, 3) vertices and (t, 3) triangles. */
static int mesh_of_arrays(PyObject* vertices, PyObject* triangles, const char* function, sb_mesh* mesh) {
    PyArrayObject* x = sbpy_array(vertices, function, "vertices", NPY_DOUBLE, 3);
    PyArrayObject* t = x ? sbpy_index_array(triangles, function, "triangles", 3) : NULL;
    if (!t) {
        Py_XDECREF(x);
        return -1;
    }
    *mesh = (sb_mesh){(uint32_t)PyArray_DIM(x, 0), malloc((size_t)PyArray_SIZE(x) * sizeof(double) + 1),
                      (uint32_t)PyArray_DIM(t, 0), malloc((size_t)PyArray_SIZE(t) * sizeof(uint32_t) + 1)};
    if (mesh->positions && mesh->triangles) {
        memcpy(mesh->positions, PyArray_DATA(x), (size_t)PyArray_SIZE(x) * sizeof(double));
        const int64_t* tv = PyArray_DATA(t);
        for (npy_intp i = 0; i < PyArray_SIZE(t); i++) mesh->triangles[i] = (uint32_t)tv[i];
    }
    Py_DECREF(x);
    Py_DECREF(t);
    if (!mesh->positions || !mesh->triangles) {
        sb_mesh_free(mesh);
        PyErr_NoMemory();
        return -1;
    }
    return 0;
}

static PyObject* model_from_mesh(PyObject* cls, PyObject* args, PyObject* kwargs) {
    (void)cls;
    static const char* function = "Model.from_mesh()";
    PyObject *vertices, *triangles;
    if (!PyArg_ParseTuple(args, "OO:from_mesh", &vertices, &triangles)) return NULL;
    mesh_options options;
    sb_mesh mesh;
    if (read_mesh_kwargs(function, kwargs, NULL, 0, &options) < 0 ||
        mesh_of_arrays(vertices, triangles, function, &mesh) < 0)
        return NULL;
    return model_of_mesh(&mesh, &options, function);
}

/** The Spring Systems factory (sb_builder_add_spring_mesh) over a triangle mesh. */
static PyObject* model_spring_mesh(PyObject* cls, PyObject* args, PyObject* kwargs) {
    (void)cls;
    static const char* function = "Model.spring_mesh()";
    PyObject *vertices, *triangles, *fixed = NULL;
    if (!PyArg_ParseTuple(args, "OO:spring_mesh", &vertices, &triangles)) return NULL;
    sb_spring_mesh_def def = sb_default_spring_mesh_def();
    sbpy_option table[] = {
        {"stretch_k", SBPY_DOUBLE, &def.stretch_k, NULL},
        {"stretch_damping", SBPY_DOUBLE, &def.stretch_damping, NULL},
        {"bend_k", SBPY_DOUBLE, &def.bend_k, NULL},
        {"bend_damping", SBPY_DOUBLE, &def.bend_damping, NULL},
        {"vicinity", SBPY_DOUBLE, &def.vicinity, NULL},
        {"vicinity_k", SBPY_DOUBLE, &def.vicinity_k, NULL},
        {"vicinity_damping", SBPY_DOUBLE, &def.vicinity_damping, NULL},
        {"mass", SBPY_DOUBLE, &def.mass, NULL},
        {"density", SBPY_DOUBLE, &def.density, NULL},
        {"break_strain", SBPY_DOUBLE, &def.break_strain, NULL},
        {"fixed", SBPY_OBJECT, &fixed, NULL},
    };
    sb_mesh mesh;
    if (sbpy_options(function, kwargs, table, sizeof table / sizeof table[0]) < 0 ||
        mesh_of_arrays(vertices, triangles, function, &mesh) < 0)
        return NULL;
    sb_builder* builder = sb_builder_create();
    sb_error err = {{0}};
    sb_status status = builder ? sb_builder_add_spring_mesh(builder, &mesh, &def, &err) : SB_ERR_NOMEM;
    sb_mesh_free(&mesh);
    if (status != SB_OK) {
        sb_builder_destroy(builder);
        return sbpy_raise(status, err.message);
    }
    if (pin(builder, fixed, function) < 0) {
        sb_builder_destroy(builder);
        return NULL;
    }
    return compile(builder);
}

static PyObject* model_sheet(PyObject* cls, PyObject* args, PyObject* kwargs) {
    (void)cls;
    static const char* function = "Model.sheet()";
    if (PyTuple_GET_SIZE(args)) return PyErr_Format(PyExc_TypeError, "%s takes keyword arguments only", function);
    sb_sheet_def def = sb_default_sheet_def();
    int nx = (int)def.nx, ny = (int)def.ny;
    double seed = (double)def.seed;
    sbpy_option own[] = {{"nx", SBPY_INT, &nx, NULL},
                         {"ny", SBPY_INT, &ny, NULL},
                         {"width", SBPY_DOUBLE, &def.width, NULL},
                         {"height", SBPY_DOUBLE, &def.height, NULL},
                         {"jitter", SBPY_DOUBLE, &def.jitter, NULL},
                         {"seed", SBPY_DOUBLE, &seed, NULL}};
    mesh_options options;
    if (read_mesh_kwargs(function, kwargs, own, sizeof own / sizeof own[0], &options) < 0) return NULL;
    if (nx < 2 || ny < 2)
        return PyErr_Format(PyExc_ValueError, "%s: 'nx' and 'ny' must be at least 2 (got %d, %d)", function, nx, ny);
    def.nx = (uint32_t)nx;
    def.ny = (uint32_t)ny;
    def.seed = (uint64_t)seed;
    sb_mesh mesh = {0};
    sb_error err = {{0}};
    sb_status status = sb_mesh_generate_sheet(&def, &mesh, &err);
    if (status != SB_OK) return sbpy_raise(status, err.message);
    return model_of_mesh(&mesh, &options, function);
}

static PyObject* model_icosphere(PyObject* cls, PyObject* args, PyObject* kwargs) {
    (void)cls;
    static const char* function = "Model.icosphere()";
    if (PyTuple_GET_SIZE(args)) return PyErr_Format(PyExc_TypeError, "%s takes keyword arguments only", function);
    int subdivisions = 2;
    double radius = 1.0;
    sbpy_option own[] = {{"subdivisions", SBPY_INT, &subdivisions, NULL}, {"radius", SBPY_DOUBLE, &radius, NULL}};
    mesh_options options;
    if (read_mesh_kwargs(function, kwargs, own, 2, &options) < 0) return NULL;
    if (subdivisions < 0 || subdivisions > 10)
        return PyErr_Format(PyExc_ValueError, "%s: 'subdivisions' must be 0 to 10 (got %d)", function, subdivisions);
    sb_mesh mesh = {0};
    sb_error err = {{0}};
    sb_status status = sb_mesh_generate_icosphere((uint32_t)subdivisions, radius, &mesh, &err);
    if (status != SB_OK) return sbpy_raise(status, err.message);
    return model_of_mesh(&mesh, &options, function);
}

static PyObject* model_load(PyObject* cls, PyObject* args, PyObject* kwargs) {
    (void)cls;
    static const char* function = "Model.load()";
    PyObject* path_object;
    if (!PyArg_ParseTuple(args, "O&:load", PyUnicode_FSConverter, &path_object)) return NULL;
    mesh_options options;
    if (read_mesh_kwargs(function, kwargs, NULL, 0, &options) < 0) {
        Py_DECREF(path_object);
        return NULL;
    }
    sb_mesh mesh = {0};
    sb_error err = {{0}};
    sb_status status;
    Py_BEGIN_ALLOW_THREADS status = sb_mesh_load(PyBytes_AS_STRING(path_object), &mesh, &err);
    Py_END_ALLOW_THREADS Py_DECREF(path_object);
    if (status != SB_OK) return sbpy_raise(status, err.message);
    return model_of_mesh(&mesh, &options, function);
}

/* ---- from a tetrahedral mesh: the tissue factories ---- */

static PyObject* model_from_tets(PyObject* cls, PyObject* args, PyObject* kwargs) {
    (void)cls;
    static const char* function = "Model.from_tets()";
    PyObject *vertices, *tets, *fixed = NULL;
    const char* model_name = NULL;
    const char* tissue_name = NULL;
    sb_tissue_def tissue = sb_default_tissue_def();
    if (!PyArg_ParseTuple(args, "OO:from_tets", &vertices, &tets)) return NULL;
    sbpy_option table[] = {{"tissue", SBPY_STRING, &tissue_name, NULL},
                           {"young_modulus", SBPY_DOUBLE, &tissue.young_modulus, NULL},
                           {"density", SBPY_DOUBLE, &tissue.density, NULL},
                           {"damping", SBPY_DOUBLE, &tissue.damping, NULL},
                           {"poisson_ratio", SBPY_DOUBLE, &tissue.poisson_ratio, NULL},
                           {"stiffness_damping", SBPY_DOUBLE, &tissue.stiffness_damping, NULL},
                           {"model", SBPY_STRING, &model_name, NULL},
                           {"fixed", SBPY_OBJECT, &fixed, NULL}};
    if (kwargs) {
        PyObject* name = PyDict_GetItemString(kwargs, "tissue");
        if (name && PyUnicode_Check(name) && !sb_tissue_from_name(PyUnicode_AsUTF8(name), &tissue))
            return PyErr_Format(PyExc_ValueError, "%s: 'tissue' must be 'liver' or 'gallbladder', not '%U'", function,
                                name);
    }
    if (sbpy_options(function, kwargs, table, sizeof table / sizeof table[0]) < 0) return NULL;
    if (model_name && strcmp(model_name, "corotated") == 0)
        tissue.model = SB_TISSUE_COROTATED;
    else if (model_name && strcmp(model_name, "corotated_quadratic") == 0)
        tissue.model = SB_TISSUE_COROTATED_QUADRATIC;
    else if (model_name && strcmp(model_name, "springs") != 0)
        return PyErr_Format(PyExc_ValueError,
                            "%s: 'model' must be 'springs', 'corotated' or 'corotated_quadratic', not '%s'", function,
                            model_name);
    PyArrayObject* x = sbpy_array(vertices, function, "vertices", NPY_DOUBLE, 3);
    PyArrayObject* t = x ? sbpy_index_array(tets, function, "tetrahedra", 4) : NULL;
    if (!t) {
        Py_XDECREF(x);
        return NULL;
    }
    uint32_t* corners = PyMem_Malloc((size_t)PyArray_SIZE(t) * sizeof(uint32_t) + 1);
    if (!corners) {
        Py_DECREF(x);
        Py_DECREF(t);
        return PyErr_NoMemory();
    }
    const int64_t* tv = PyArray_DATA(t);
    for (npy_intp i = 0; i < PyArray_SIZE(t); i++) corners[i] = (uint32_t)tv[i];
    sb_tet_mesh mesh = {(uint32_t)PyArray_DIM(x, 0), PyArray_DATA(x), (uint32_t)PyArray_DIM(t, 0), corners};
    sb_builder* builder = sb_builder_create();
    sb_error err = {{0}};
    sb_status status = builder ? sb_builder_add_tet_mesh(builder, &mesh, &tissue, &err) : SB_ERR_NOMEM;
    PyMem_Free(corners);
    Py_DECREF(x);
    Py_DECREF(t);
    if (status != SB_OK) {
        sb_builder_destroy(builder);
        return sbpy_raise(status, err.message);
    }
    if (pin(builder, fixed, function) < 0) {
        sb_builder_destroy(builder);
        return NULL;
    }
    return compile(builder);
}

/* ---- the scalar reference ---- */

static PyObject* model_reference_forces(SbpyModel* self, PyObject* args, PyObject* kwargs) {
    static const char* function = "Model.reference_forces()";
    static char* keywords[] = {"positions", "velocities", NULL};
    PyObject *positions, *velocities = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O|O:reference_forces", keywords, &positions, &velocities))
        return NULL;
    npy_intp n = sb_model_vertex_count(self->model);
    PyArrayObject* x = sbpy_array(positions, function, "positions", NPY_DOUBLE, 3);
    PyArrayObject* v =
        x && velocities != Py_None ? sbpy_array(velocities, function, "velocities", NPY_DOUBLE, 3) : NULL;
    npy_intp dims[2] = {n, 3};
    PyObject* forces = NULL;
    if (!x || (velocities != Py_None && !v)) goto done;
    if (PyArray_DIM(x, 0) != n || (v && PyArray_DIM(v, 0) != n)) {
        PyErr_Format(PyExc_ValueError, "%s: 'positions' and 'velocities' must have %zd rows", function, (Py_ssize_t)n);
        goto done;
    }
    forces = PyArray_ZEROS(2, dims, NPY_DOUBLE, 0);
    if (!forces) goto done;
    sb_energies energies;
    memset(&energies, 0, sizeof energies);
    sb_error err = {{0}};
    sb_status status = sb_reference_forces(self->model, PyArray_DATA(x), v ? PyArray_DATA(v) : NULL,
                                           PyArray_DATA((PyArrayObject*)forces), &energies, &err);
    if (status != SB_OK) {
        Py_CLEAR(forces);
        sbpy_raise(status, err.message);
        goto done;
    }
    PyObject* terms = PyDict_New();
    for (int t = 0; terms && t < SB_TERM_COUNT; t++) {
        PyObject* value = PyFloat_FromDouble(energies.term[t]);
        if (!value || PyDict_SetItemString(terms, sb_term_name((sb_term)t), value) < 0) Py_CLEAR(terms);
        Py_XDECREF(value);
    }
    PyObject* result = terms ? PyTuple_Pack(2, forces, terms) : NULL;
    Py_XDECREF(terms);
    Py_DECREF(forces);
    forces = result;
done:
    Py_XDECREF(x);
    Py_XDECREF(v);
    return forces;
}

/* ---- what a model holds ---- */

static PyObject* model_vertex_count(SbpyModel* self, void* closure) {
    (void)closure;
    return PyLong_FromUnsignedLong(sb_model_vertex_count(self->model));
}
static PyObject* model_bond_count(SbpyModel* self, void* closure) {
    (void)closure;
    return PyLong_FromUnsignedLong(sb_model_bond_count(self->model));
}
static PyObject* model_triangle_count(SbpyModel* self, void* closure) {
    (void)closure;
    return PyLong_FromUnsignedLong(sb_model_triangle_count(self->model));
}
static PyObject* model_tet_count(SbpyModel* self, void* closure) {
    (void)closure;
    return PyLong_FromUnsignedLong(sb_model_tet_count(self->model));
}
static PyObject* model_hinge_count(SbpyModel* self, void* closure) {
    (void)closure;
    return PyLong_FromUnsignedLong(sb_model_hinge_count(self->model));
}

/** An (n, 3) float64 array of a per-vertex vector. */
static PyObject* vertex_vectors(SbpyModel* self, void (*get)(const sb_model*, uint32_t, double*)) {
    npy_intp dims[2] = {sb_model_vertex_count(self->model), 3};
    PyObject* array = PyArray_SimpleNew(2, dims, NPY_DOUBLE);
    if (!array) return NULL;
    double* out = PyArray_DATA((PyArrayObject*)array);
    for (npy_intp v = 0; v < dims[0]; v++) get(self->model, (uint32_t)v, out + 3 * v);
    return array;
}
static PyObject* model_rest_positions(SbpyModel* self, void* closure) {
    (void)closure;
    return vertex_vectors(self, sb_model_rest_position);
}
static PyObject* model_initial_velocities(SbpyModel* self, void* closure) {
    (void)closure;
    return vertex_vectors(self, sb_model_initial_velocity);
}

static PyObject* model_masses(SbpyModel* self, void* closure) {
    (void)closure;
    npy_intp n = sb_model_vertex_count(self->model);
    PyObject* array = PyArray_SimpleNew(1, &n, NPY_DOUBLE);
    if (!array) return NULL;
    double* out = PyArray_DATA((PyArrayObject*)array);
    for (npy_intp v = 0; v < n; v++) out[v] = sb_model_mass(self->model, (uint32_t)v);
    return array;
}

static PyObject* model_fixed(SbpyModel* self, void* closure) {
    (void)closure;
    npy_intp n = sb_model_vertex_count(self->model);
    PyObject* array = PyArray_SimpleNew(1, &n, NPY_BOOL);
    if (!array) return NULL;
    npy_bool* out = PyArray_DATA((PyArrayObject*)array);
    for (npy_intp v = 0; v < n; v++) out[v] = sb_model_is_fixed(self->model, (uint32_t)v);
    return array;
}

static PyObject* model_triangles(SbpyModel* self, void* closure) {
    (void)closure;
    npy_intp dims[2] = {sb_model_triangle_count(self->model), 3};
    PyObject* array = PyArray_SimpleNew(2, dims, NPY_UINT32);
    if (!array) return NULL;
    uint32_t* out = PyArray_DATA((PyArrayObject*)array);
    for (npy_intp t = 0; t < dims[0]; t++) sb_model_triangle(self->model, (uint32_t)t, out + 3 * t);
    return array;
}

static PyObject* model_bonds(SbpyModel* self, void* closure) {
    (void)closure;
    npy_intp dims[2] = {sb_model_bond_count(self->model), 2};
    PyObject* array = PyArray_SimpleNew(2, dims, NPY_UINT32);
    if (!array) return NULL;
    uint32_t* out = PyArray_DATA((PyArrayObject*)array);
    for (npy_intp b = 0; b < dims[0]; b++) {
        sb_bond_info info = sb_model_bond(self->model, (uint32_t)b);
        out[2 * b] = info.i;
        out[2 * b + 1] = info.j;
    }
    return array;
}

static PyObject* model_rest_lengths(SbpyModel* self, void* closure) {
    (void)closure;
    npy_intp n = sb_model_bond_count(self->model);
    PyObject* array = PyArray_SimpleNew(1, &n, NPY_DOUBLE);
    if (!array) return NULL;
    double* out = PyArray_DATA((PyArrayObject*)array);
    for (npy_intp b = 0; b < n; b++) out[b] = sb_model_bond(self->model, (uint32_t)b).rest_length;
    return array;
}

static PyObject* model_terms(SbpyModel* self, void* closure) {
    (void)closure;
    PyObject* terms = PyList_New(0);
    for (int t = 0; terms && t < SB_TERM_COUNT; t++) {
        if (!sb_model_term_enabled(self->model, (sb_term)t)) continue;
        PyObject* name = PyUnicode_FromString(sb_term_name((sb_term)t));
        if (!name || PyList_Append(terms, name) < 0) Py_CLEAR(terms);
        Py_XDECREF(name);
    }
    return terms;
}

static PyObject* model_repr(SbpyModel* self) {
    return PyUnicode_FromFormat("<softbond.Model: %u vertices, %u bonds, %u triangles, %u tetrahedra>",
                                sb_model_vertex_count(self->model), sb_model_bond_count(self->model),
                                sb_model_triangle_count(self->model), sb_model_tet_count(self->model));
}

static PyObject* model_new(PyTypeObject* type, PyObject* args, PyObject* kwargs) {
    (void)type, (void)args, (void)kwargs;
    return PyErr_Format(PyExc_TypeError, "make a Model with Model.from_arrays, from_mesh, from_tets, sheet, "
                                         "icosphere or load, or take a Scene's");
}

static PyGetSetDef model_getset[] = {
    {"vertex_count", (getter)model_vertex_count, NULL, "Vertices (int).", NULL},
    {"bond_count", (getter)model_bond_count, NULL, "Bonds (int), in the order they were added.", NULL},
    {"triangle_count", (getter)model_triangle_count, NULL, "Triangles (int).", NULL},
    {"tet_count", (getter)model_tet_count, NULL, "Co-rotated tetrahedra (int).", NULL},
    {"hinge_count", (getter)model_hinge_count, NULL, "Hinges (int).", NULL},
    {"rest_positions", (getter)model_rest_positions, NULL, "Rest positions, m: a new (n, 3) float64 array.", NULL},
    {"initial_velocities", (getter)model_initial_velocities, NULL, "Initial velocities, m/s: a new (n, 3) array.",
     NULL},
    {"masses", (getter)model_masses, NULL, "Vertex masses, kg: a new (n,) float64 array.", NULL},
    {"fixed", (getter)model_fixed, NULL, "Which vertices are pinned: a new (n,) bool array.", NULL},
    {"triangles", (getter)model_triangles, NULL, "Triangles' corners: a new (t, 3) uint32 array.", NULL},
    {"bonds", (getter)model_bonds, NULL, "Bonds' ends: a new (b, 2) uint32 array.", NULL},
    {"rest_lengths", (getter)model_rest_lengths, NULL, "Bonds' rest lengths, m: a new (b,) float64 array.", NULL},
    {"terms", (getter)model_terms, NULL, "The force terms the model carries (names from softbond.TERMS).", NULL},
    {NULL}};

static PyMethodDef model_methods[] = {
    {"from_arrays", (PyCFunction)(void (*)(void))model_from_arrays, METH_VARARGS | METH_KEYWORDS | METH_CLASS,
     "from_arrays(vertices, *, masses=1.0, velocities=None, fixed=None, bonds=None, bond_k=0, spring_k=0,\n"
     "            spring_damping=0, rest_lengths=-1, break_min=0, break_max=inf, triangles=None, angle_k=0,\n"
     "            stretch_bend_k=0, tetrahedra=None, young_modulus=0, poisson_ratio=0.3, hinges=None,\n"
     "            bend_k=0) -> Model\n\n"
     "A model from arrays: vertices (n, 3) m; bonds (b, 2), triangles (t, 3), tetrahedra (e, 4) and hinges\n"
     "(h, 4) vertex indices (a hinge e0, e1, o0, o1: the edge e0-e1 shared by the triangles (e0, e1, o0) and\n"
     "(e1, e0, o1)). Every constant is a number for all elements or an array with one per element: masses\n"
     "kg, bond_k and spring_k N/m, spring_damping N s/m, rest_lengths m (negative: the current distance),\n"
     "break_min/break_max m (breakage limits), angle_k J, stretch_bend_k J/m, young_modulus Pa, bend_k\n"
     "J/rad^2. fixed: vertex indices or an (n,) bool mask. Raises InvalidError naming the first bad element."},
    {"from_mesh", (PyCFunction)(void (*)(void))model_from_mesh, METH_VARARGS | METH_KEYWORDS | METH_CLASS,
     "from_mesh(vertices, triangles, *, bond_k=100, angle_k=0.1, stretch_bend_k=0, spring_k=0, spring_damping=0,\n"
     "          bend_k=0, mass=0.01, density=0, break_strain=0, fixed=None) -> Model\n\n"
     "The molecular factory over a triangle mesh: a bond per unique edge, the triangles' angle terms, a hinge\n"
     "per interior edge when bend_k > 0; mass per vertex (kg) or an areal density (kg/m^2)."},
    {"spring_mesh", (PyCFunction)(void (*)(void))model_spring_mesh, METH_VARARGS | METH_KEYWORDS | METH_CLASS,
     "spring_mesh(vertices, triangles, *, stretch_k=100, stretch_damping=0.1, bend_k=10, bend_damping=0.01,\n"
     "            vicinity=0, vicinity_k=100, vicinity_damping=0.1, mass=0.01, density=0, break_strain=0,\n"
     "            fixed=None) -> Model\n\n"
     "The Spring Systems factory: a damped spring per edge, a bend spring across each interior edge, and\n"
     "vicinity springs between vertices nearer than `vicinity` (m) not joined yet."},
    {"reference_forces", (PyCFunction)(void (*)(void))model_reference_forces, METH_VARARGS | METH_KEYWORDS,
     "reference_forces(positions, velocities=None) -> (forces, energies)\n\n"
     "Every term's forces at the given (n, 3) positions by the double scalar reference: an (n, 3) array (N,\n"
     "internal forces only) and a dict of each term's energy (J). DegenerateError names a collapsed element."},
    {"sheet", (PyCFunction)(void (*)(void))model_sheet, METH_VARARGS | METH_KEYWORDS | METH_CLASS,
     "sheet(*, nx=10, ny=10, width=1, height=1, jitter=0, seed=1, **material) -> Model\n\n"
     "A rectangular sheet in z = 0 (vertex = row * nx + column) through the molecular factory; the material\n"
     "keywords are from_mesh's."},
    {"icosphere", (PyCFunction)(void (*)(void))model_icosphere, METH_VARARGS | METH_KEYWORDS | METH_CLASS,
     "icosphere(*, subdivisions=2, radius=1, **material) -> Model\n\nAn icosphere about the origin (from_mesh's "
     "material keywords)."},
    {"load", (PyCFunction)(void (*)(void))model_load, METH_VARARGS | METH_KEYWORDS | METH_CLASS,
     "load(path, **material) -> Model\n\nA triangle mesh file (OBJ, OFF, anything assimp reads, the surface of a\n"
     "tetrahedral mesh) through the molecular factory. FileError or ParseError name the file and line."},
    {"from_tets", (PyCFunction)(void (*)(void))model_from_tets, METH_VARARGS | METH_KEYWORDS | METH_CLASS,
     "from_tets(vertices, tetrahedra, *, tissue='liver', young_modulus=3500, density=1060, damping=1,\n"
     "          poisson_ratio=0.3, stiffness_damping=0, model='springs', fixed=None) -> Model\n\n"
     "Soft tissue from a tetrahedral mesh and Young's modulus (Pa): model='springs' (damped edge springs, E\n"
     "only), 'corotated' (co-rotated linear FEM, E and Poisson's ratio) or 'corotated_quadratic' (10-node\n"
     "elements, a vertex added at each edge's middle: no locking in bending). tissue names a preset (liver,\n"
     "gallbladder) that the other keywords then change. stiffness_damping is Rayleigh's beta (s)."},
    {NULL}};

PyTypeObject SbpyModelType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "softbond.Model",
    .tp_basicsize = sizeof(SbpyModel),
    .tp_dealloc = (destructor)model_dealloc,
    .tp_repr = (reprfunc)model_repr,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A compiled, immutable model: vertices (mass points), bonds, triangles, hinges, tetrahedra.\n\n"
              "Make one with the class methods from_arrays, from_mesh, from_tets, sheet, icosphere, load, or\n"
              "take Scene.model. Any number of solvers may share one model; it lives while any of them does.",
    .tp_methods = model_methods,
    .tp_getset = model_getset,
    .tp_new = model_new,
};
