/* softbond.Collider and softbond.Handle: what the bodies touch and what
 * holds them. A collider is a built-in shape (plane, sphere, capsule, box,
 * triangle mesh; static, kinematic with a keyframed path or a pose set every
 * step, or dynamic with a mass) or a program's own, whose collide callback
 * is a Python callable: the solver's threads call it for every vertex move
 * that reaches its bounds, each call taking the GIL. */
#include "sbpy.h"

#include <math.h>

/* ---- colliders ---- */

/** The (n, 3) vertices and (t, 3) triangles of a mesh collider, as an sb_mesh (PyMem arrays). */
static int collider_mesh(PyObject* vertices, PyObject* triangles, sb_mesh* mesh) {
    static const char* function = "Collider()";
    if (!vertices || !triangles || vertices == Py_None || triangles == Py_None) {
        PyErr_Format(PyExc_TypeError, "%s: shape 'mesh' needs 'vertices' and 'triangles'", function);
        return -1;
    }
    PyArrayObject* x = sbpy_array(vertices, function, "vertices", NPY_DOUBLE, 3);
    PyArrayObject* t = x ? sbpy_index_array(triangles, function, "triangles", 3) : NULL;
    if (!t) {
        Py_XDECREF(x);
        return -1;
    }
    mesh->vertex_count = (uint32_t)PyArray_DIM(x, 0);
    mesh->triangle_count = (uint32_t)PyArray_DIM(t, 0);
    mesh->positions = PyMem_Malloc((size_t)PyArray_SIZE(x) * sizeof(double) + 1);
    mesh->triangles = PyMem_Malloc((size_t)PyArray_SIZE(t) * sizeof(uint32_t) + 1);
    if (mesh->positions && mesh->triangles) {
        memcpy(mesh->positions, PyArray_DATA(x), (size_t)PyArray_SIZE(x) * sizeof(double));
        const int64_t* tv = PyArray_DATA(t);
        for (npy_intp i = 0; i < PyArray_SIZE(t); i++) mesh->triangles[i] = (uint32_t)tv[i];
    }
    Py_DECREF(x);
    Py_DECREF(t);
    if (!mesh->positions || !mesh->triangles) {
        PyErr_NoMemory();
        return -1;
    }
    return 0;
}

static int collider_init(SbpyCollider* self, PyObject* args, PyObject* kwargs) {
    static const char* function = "Collider()";
    const char* shape_name;
    if (self->collider) {
        PyErr_Format(PyExc_RuntimeError, "%s: already created", function);
        return -1;
    }
    if (!PyArg_ParseTuple(args, "s:Collider", &shape_name)) return -1;
    sb_collider_def def = sb_default_collider_def();
    const char* interpolation = NULL;
    PyObject *path = NULL, *vertices = NULL, *triangles = NULL;
    sbpy_option table[] = {
        {"name", SBPY_STRING, &def.name, NULL},
        {"point", SBPY_VEC3, def.point, NULL},
        {"normal", SBPY_VEC3, def.normal, NULL},
        {"center", SBPY_VEC3, def.center, NULL},
        {"radius", SBPY_DOUBLE, &def.radius, NULL},
        {"a", SBPY_VEC3, def.a, NULL},
        {"b", SBPY_VEC3, def.b, NULL},
        {"half_extents", SBPY_VEC3, def.half_extents, NULL},
        {"rotate", SBPY_VEC3, def.rotate, NULL},
        {"vertices", SBPY_OBJECT, &vertices, NULL},
        {"triangles", SBPY_OBJECT, &triangles, NULL},
        {"friction", SBPY_DOUBLE, &def.friction, NULL},
        {"static_friction", SBPY_DOUBLE, &def.static_friction, NULL},
        {"restitution", SBPY_DOUBLE, &def.restitution, NULL},
        {"thickness", SBPY_DOUBLE, &def.thickness, NULL},
        {"footprint", SBPY_DOUBLE, &def.footprint, NULL},
        {"path", SBPY_OBJECT, &path, NULL},
        {"interpolation", SBPY_STRING, &interpolation, NULL},
        {"mass", SBPY_DOUBLE, &def.mass, NULL},
        {"velocity", SBPY_VEC3, def.velocity, NULL},
        {"angular_velocity", SBPY_VEC3, def.angular_velocity, NULL},
    };
    if (sbpy_options(function, kwargs, table, sizeof table / sizeof table[0]) < 0) return -1;
    if (!sb_collider_shape_from_name(shape_name, &def.shape)) {
        PyErr_Format(PyExc_ValueError, "%s: 'shape' must be plane, sphere, capsule, box or mesh, not '%s'", function,
                     shape_name);
        return -1;
    }
    if (sbpy_interpolation(interpolation, function, &def.interpolation) < 0) return -1;
    sb_keyframe* frames = NULL;
    sb_mesh mesh = {0};
    if (sbpy_keyframes(path, function, &frames, &def.path_count) < 0) return -1;
    def.path = frames;
    if (def.shape == SB_COLLIDER_MESH) {
        if (collider_mesh(vertices, triangles, &mesh) < 0) {
            PyMem_Free(frames);
            PyMem_Free(mesh.positions);
            PyMem_Free(mesh.triangles);
            return -1;
        }
        def.mesh = &mesh;
    }
    sb_error err = {{0}};
    self->collider = sb_collider_create(&def, &err);
    PyMem_Free(frames);
    PyMem_Free(mesh.positions);
    PyMem_Free(mesh.triangles);
    if (!self->collider) {
        sbpy_raise(SB_ERR_INVALID, err.message);
        return -1;
    }
    return 0;
}

/* A program's own collider: the callables' trampolines. */

static bool custom_collide(void* user, const sb_contact_query* q, sb_contact* contact) {
    SbpyCollider* self = user;
    bool touched = false;
    PyGILState_STATE gil = PyGILState_Ensure();
    if (!self->pending.type && self->collide) {
        PyObject* result = PyObject_CallFunction(self->collide, "Idd(ddd)(ddd)d", q->vertex, q->t0, q->t1, q->from[0],
                                                 q->from[1], q->from[2], q->to[0], q->to[1], q->to[2], q->thickness);
        PyObject *normal = NULL, *velocity = NULL;
        if (result && result != Py_None) {
            memset(contact, 0, sizeof *contact);
            static char* keywords[] = {"fraction", "depth", "normal", "velocity", "restitution", "friction", NULL};
            PyObject* no_args = PyTuple_New(0);
            touched =
                no_args && PyDict_Check(result) &&
                PyArg_ParseTupleAndKeywords(no_args, result, "|ddOOdd", keywords, &contact->fraction, &contact->depth,
                                            &normal, &velocity, &contact->restitution, &contact->friction) &&
                normal && sbpy_vec3(normal, "collide", "normal", contact->normal) == 0 &&
                (!velocity || sbpy_vec3(velocity, "collide", "velocity", contact->velocity) == 0);
            Py_XDECREF(no_args);
            if (!touched && !PyErr_Occurred())
                PyErr_SetString(PyExc_TypeError,
                                "collide must return None or a dict with 'fraction', 'depth' and 'normal'");
            contact->static_friction = contact->friction;
        }
        if (!result || PyErr_Occurred()) {
            touched = false;
            sbpy_pending_keep(&self->pending);
        }
        Py_XDECREF(result);
    }
    PyGILState_Release(gil);
    return touched;
}

static void custom_begin_step(void* user, double t0, double t1) {
    SbpyCollider* self = user;
    PyGILState_STATE gil = PyGILState_Ensure();
    if (!self->pending.type && self->begin_step) {
        PyObject* result = PyObject_CallFunction(self->begin_step, "dd", t0, t1);
        if (!result) sbpy_pending_keep(&self->pending);
        Py_XDECREF(result);
    }
    PyGILState_Release(gil);
}

static PyObject* collider_custom(PyObject* cls, PyObject* args, PyObject* kwargs) {
    static char* keywords[] = {"collide", "begin_step", "name", "bounds", NULL};
    PyObject *collide, *begin_step = Py_None, *bounds = Py_None;
    const char* name = "custom";
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O|$OsO:custom", keywords, &collide, &begin_step, &name, &bounds))
        return NULL;
    if (!PyCallable_Check(collide))
        return PyErr_Format(PyExc_TypeError, "Collider.custom(): 'collide' must be callable");
    if (begin_step != Py_None && !PyCallable_Check(begin_step))
        return PyErr_Format(PyExc_TypeError, "Collider.custom(): 'begin_step' must be callable or None");
    double lo[3], hi[3];
    if (bounds != Py_None) {
        PyObject* pair = PySequence_Check(bounds) ? PySequence_Tuple(bounds) : NULL;
        bool good = pair && PyTuple_GET_SIZE(pair) == 2 &&
                    sbpy_vec3(PyTuple_GET_ITEM(pair, 0), "Collider.custom()", "bounds[0]", lo) == 0 &&
                    sbpy_vec3(PyTuple_GET_ITEM(pair, 1), "Collider.custom()", "bounds[1]", hi) == 0;
        Py_XDECREF(pair);
        if (!good) {
            PyErr_Clear();
            return PyErr_Format(PyExc_TypeError, "Collider.custom(): 'bounds' must be ((x, y, z), (x, y, z))");
        }
    }
    SbpyCollider* self = (SbpyCollider*)((PyTypeObject*)cls)->tp_alloc((PyTypeObject*)cls, 0);
    if (!self) return NULL;
    self->collide = Py_NewRef(collide);
    self->begin_step = begin_step == Py_None ? NULL : Py_NewRef(begin_step);
    sb_error err = {{0}};
    self->collider = sb_collider_create_custom(name, custom_collide, custom_begin_step, self, &err);
    if (!self->collider) {
        Py_DECREF(self);
        return sbpy_raise(SB_ERR_INVALID, err.message);
    }
    if (bounds != Py_None) sb_collider_set_bounds(self->collider, lo, hi);
    return (PyObject*)self;
}

static int collider_clear(SbpyCollider* self) {
    Py_CLEAR(self->collide);
    Py_CLEAR(self->begin_step);
    Py_CLEAR(self->pending.type);
    Py_CLEAR(self->pending.value);
    Py_CLEAR(self->pending.traceback);
    return 0;
}

static void collider_dealloc(SbpyCollider* self) {
    PyObject_GC_UnTrack(self);
    if (self->owner)
        Py_CLEAR(self->owner);
    else
        sb_collider_destroy(self->collider);
    collider_clear(self);
    Py_TYPE(self)->tp_free((PyObject*)self);
}

static int collider_traverse(SbpyCollider* self, visitproc visit, void* arg) {
    Py_VISIT(self->collide);
    Py_VISIT(self->begin_step);
    return 0;
}

/** set_pose(translate, rotate=(0, 0, 0)) of a collider or a handle. */
static int pose_arguments(PyObject* args, PyObject* kwargs, double t[3], double r[3]) {
    static char* keywords[] = {"translate", "rotate", NULL};
    PyObject *translate, *rotate = NULL;
    r[0] = r[1] = r[2] = 0;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O|O:set_pose", keywords, &translate, &rotate) ||
        sbpy_vec3(translate, "set_pose()", "translate", t) < 0 ||
        (rotate && sbpy_vec3(rotate, "set_pose()", "rotate", r) < 0))
        return -1;
    return 0;
}

static PyObject* collider_set_pose(SbpyCollider* self, PyObject* args, PyObject* kwargs) {
    double t[3], r[3];
    if (pose_arguments(args, kwargs, t, r) < 0) return NULL;
    sb_collider_set_pose(self->collider, t, r);
    Py_RETURN_NONE;
}

static PyObject* collider_position(SbpyCollider* self, void* closure) {
    (void)closure;
    double x[3];
    sb_collider_state(self->collider, x, NULL);
    return sbpy_vector3(x);
}
static PyObject* collider_velocity(SbpyCollider* self, void* closure) {
    (void)closure;
    double v[3];
    sb_collider_state(self->collider, NULL, v);
    return sbpy_vector3(v);
}
static PyObject* collider_rotation(SbpyCollider* self, void* closure) {
    (void)closure;
    double r[9];
    sb_collider_orientation(self->collider, r, NULL);
    npy_intp dims[2] = {3, 3};
    PyObject* array = PyArray_SimpleNew(2, dims, NPY_DOUBLE);
    if (array) memcpy(PyArray_DATA((PyArrayObject*)array), r, sizeof r);
    return array;
}
static PyObject* collider_angular_velocity(SbpyCollider* self, void* closure) {
    (void)closure;
    double w[3];
    sb_collider_orientation(self->collider, NULL, w);
    return sbpy_vector3(w);
}
static PyObject* collider_name(SbpyCollider* self, void* closure) {
    (void)closure;
    return PyUnicode_FromString(sb_collider_name(self->collider));
}
static PyObject* collider_inner_radius(SbpyCollider* self, void* closure) {
    (void)closure;
    return PyFloat_FromDouble(sb_collider_inner_radius(self->collider));
}
/** Every attribute needs the library's collider: refused on an object whose __init__ did not run. */
static PyObject* collider_getattro(SbpyCollider* self, PyObject* name) {
    if (!self->collider) return PyErr_Format(PyExc_RuntimeError, "the Collider was not initialized");
    return PyObject_GenericGetAttr((PyObject*)self, name);
}

static PyObject* collider_repr(SbpyCollider* self) {
    return PyUnicode_FromFormat("<softbond.Collider '%s'>", self->collider ? sb_collider_name(self->collider) : "?");
}

static PyGetSetDef collider_getset[] = {
    {"name", (getter)collider_name, NULL, "The name (the shape's when none was given).", NULL},
    {"position", (getter)collider_position, NULL,
     "Center now, m (a dynamic collider's as the solver moved it; a plane's point, a capsule's middle).", NULL},
    {"velocity", (getter)collider_velocity, NULL, "Velocity now, m/s.", NULL},
    {"rotation", (getter)collider_rotation, NULL, "Orientation now: a (3, 3) rotation from the rest frame.", NULL},
    {"angular_velocity", (getter)collider_angular_velocity, NULL, "Angular velocity now, rad/s (world).", NULL},
    {"inner_radius", (getter)collider_inner_radius, NULL,
     "How far it may move in one step without a vertex passing its middle, m.", NULL},
    {NULL}};

static PyMethodDef collider_methods[] = {
    {"set_pose", (PyCFunction)(void (*)(void))collider_set_pose, METH_VARARGS | METH_KEYWORDS,
     "set_pose(translate, rotate=(0, 0, 0)) -> None\n\nThe pose a built-in collider reaches at the end of the next\n"
     "step (rotate: degrees about x, y, z about its reference point, then translate, m); it sweeps there\n"
     "during the step. Overrides the path from the first call. Between advances only."},
    {"custom", (PyCFunction)(void (*)(void))collider_custom, METH_VARARGS | METH_KEYWORDS | METH_CLASS,
     "custom(collide, *, begin_step=None, name='custom', bounds=None) -> Collider\n\n"
     "A program's own collider. collide(vertex, t0, t1, start, end, thickness) is called for each free\n"
     "vertex's move in each step (start and end are (x, y, z) tuples) and returns None (no contact) or a dict\n"
     "{'fraction': f in [0, 1], 'depth': m, 'normal': (x, y, z), 'velocity': (x, y, z), 'restitution': r,\n"
     "'friction': mu}. begin_step(t0, t1) is called once per step first. bounds ((lo), (hi)) limits the moves\n"
     "asked about to a box. Each call takes the GIL: slow beside a built-in shape."},
    {NULL}};

PyTypeObject SbpyColliderType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "softbond.Collider",
    .tp_basicsize = sizeof(SbpyCollider),
    .tp_dealloc = (destructor)collider_dealloc,
    .tp_traverse = (traverseproc)collider_traverse,
    .tp_clear = (inquiry)collider_clear,
    .tp_repr = (reprfunc)collider_repr,
    .tp_getattro = (getattrofunc)collider_getattro,
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_GC,
    .tp_doc = "Collider(shape, /, **fields)\n--\n\n"
              "A built-in collider: shape 'plane' (point, normal), 'sphere' (center, radius), 'capsule' (a, b,\n"
              "radius), 'box' (center, half_extents, rotate degrees) or 'mesh' (vertices (n, 3), triangles (t, 3)).\n"
              "Common fields: name, friction, static_friction, restitution, thickness (m), footprint (m, not a\n"
              "plane); kinematic: path, a list of (time, translate, rotate) keyframes with interpolation 'linear'\n"
              "or 'smooth', or set_pose() every step; dynamic (sphere, box): mass (kg), velocity, angular_velocity. Collider.custom() makes a\n"
              "program's own. Attach it to one solver at a time.",
    .tp_methods = collider_methods,
    .tp_getset = collider_getset,
    .tp_init = (initproc)collider_init,
    .tp_new = PyType_GenericNew,
};

/* ---- handles ---- */

static int handle_init(SbpyHandle* self, PyObject* args, PyObject* kwargs) {
    static const char* function = "Handle()";
    PyObject* vertex_list;
    if (self->handle) {
        PyErr_Format(PyExc_RuntimeError, "%s: already created", function);
        return -1;
    }
    if (!PyArg_ParseTuple(args, "O:Handle", &vertex_list)) return -1;
    sb_handle_def def = sb_default_handle_def();
    PyObject *center = Py_None, *path = NULL, *release_time = Py_None;
    const char* interpolation = NULL;
    sbpy_option table[] = {
        {"name", SBPY_STRING, &def.name, NULL},
        {"stiffness", SBPY_DOUBLE, &def.stiffness, NULL},
        {"damping", SBPY_DOUBLE, &def.damping, NULL},
        {"center", SBPY_OBJECT, &center, NULL},
        {"path", SBPY_OBJECT, &path, NULL},
        {"interpolation", SBPY_STRING, &interpolation, NULL},
        {"release_time", SBPY_OBJECT, &release_time, NULL},
    };
    if (sbpy_options(function, kwargs, table, sizeof table / sizeof table[0]) < 0 ||
        sbpy_interpolation(interpolation, function, &def.interpolation) < 0)
        return -1;
    if (release_time != Py_None) {
        def.release_time = PyFloat_AsDouble(release_time);
        if (def.release_time == -1.0 && PyErr_Occurred()) {
            PyErr_Format(PyExc_TypeError, "%s: 'release_time' must be a number or None", function);
            return -1;
        }
    }
    double c[3];
    if (center != Py_None) {
        if (sbpy_vec3(center, function, "center", c) < 0) return -1;
        def.center = c;
    }
    PyArrayObject* indices = sbpy_index_array(vertex_list, function, "vertices", 0);
    if (!indices) return -1;
    uint32_t* v = PyMem_Malloc((size_t)PyArray_SIZE(indices) * sizeof(uint32_t) + 1);
    sb_keyframe* frames = NULL;
    if (!v || sbpy_keyframes(path, function, &frames, &def.path_count) < 0) {
        if (!v) PyErr_NoMemory();
        PyMem_Free(v);
        Py_DECREF(indices);
        return -1;
    }
    const int64_t* iv = PyArray_DATA(indices);
    for (npy_intp i = 0; i < PyArray_SIZE(indices); i++) v[i] = (uint32_t)iv[i];
    def.vertices = v;
    def.vertex_count = (uint32_t)PyArray_SIZE(indices);
    def.path = frames;
    sb_error err = {{0}};
    self->handle = sb_handle_create(&def, &err);
    PyMem_Free(v);
    PyMem_Free(frames);
    Py_DECREF(indices);
    if (!self->handle) {
        sbpy_raise(SB_ERR_INVALID, err.message);
        return -1;
    }
    return 0;
}

static void handle_dealloc(SbpyHandle* self) {
    if (self->owner)
        Py_CLEAR(self->owner);
    else
        sb_handle_destroy(self->handle);
    Py_TYPE(self)->tp_free((PyObject*)self);
}

static PyObject* handle_set_pose(SbpyHandle* self, PyObject* args, PyObject* kwargs) {
    double t[3], r[3];
    if (pose_arguments(args, kwargs, t, r) < 0) return NULL;
    sb_handle_set_pose(self->handle, t, r);
    Py_RETURN_NONE;
}

static PyObject* handle_release(SbpyHandle* self, PyObject* unused) {
    (void)unused;
    sb_handle_release(self->handle);
    Py_RETURN_NONE;
}

static PyObject* handle_grab(SbpyHandle* self, PyObject* args) {
    PyObject* vertex = Py_None;
    if (!PyArg_ParseTuple(args, "|O:grab", &vertex)) return NULL;
    sb_status status;
    if (vertex == Py_None) {
        status = sb_handle_grab(self->handle);
    } else {
        long v = PyLong_AsLong(vertex);
        if (v == -1 && PyErr_Occurred()) return NULL;
        if (v < 0 || v > (long)UINT32_MAX)
            return PyErr_Format(PyExc_ValueError, "grab(): 'vertex' %ld is not a vertex index", v);
        status = sb_handle_grab_vertex(self->handle, (uint32_t)v);
    }
    if (status != SB_OK)
        return sbpy_raise(status, vertex == Py_None ? "grab(): the handle is not attached to a solver"
                                                    : "grab(): the handle holds more than one vertex, is not "
                                                      "attached, or the vertex is not in the model");
    Py_RETURN_NONE;
}

static PyObject* handle_held(SbpyHandle* self, void* closure) {
    (void)closure;
    return PyBool_FromLong(sb_handle_held(self->handle));
}
static PyObject* handle_force(SbpyHandle* self, void* closure) {
    (void)closure;
    double f[3];
    sb_handle_force(self->handle, f);
    return sbpy_vector3(f);
}
static PyObject* handle_targets(SbpyHandle* self, void* closure) {
    (void)closure;
    npy_intp dims[2] = {sb_handle_vertex_count(self->handle), 3};
    PyObject* array = PyArray_SimpleNew(2, dims, NPY_DOUBLE);
    if (!array) return NULL;
    double* out = PyArray_DATA((PyArrayObject*)array);
    for (npy_intp k = 0; k < dims[0]; k++) sb_handle_target(self->handle, (uint32_t)k, out + 3 * k);
    return array;
}
static PyObject* handle_name(SbpyHandle* self, void* closure) {
    (void)closure;
    return PyUnicode_FromString(sb_handle_name(self->handle));
}

/** As collider_getattro: refused before __init__. */
static PyObject* handle_getattro(SbpyHandle* self, PyObject* name) {
    if (!self->handle) return PyErr_Format(PyExc_RuntimeError, "the Handle was not initialized");
    return PyObject_GenericGetAttr((PyObject*)self, name);
}

static PyGetSetDef handle_getset[] = {
    {"held", (getter)handle_held, NULL, "Whether it holds its vertices.", NULL},
    {"force", (getter)handle_force, NULL,
     "The force (N) a soft handle exerted on the body at the last force evaluation; zeros when hard.", NULL},
    {"targets", (getter)handle_targets, NULL, "Its vertices' targets (m) at the end of the last step: (k, 3).", NULL},
    {"name", (getter)handle_name, NULL, "The name.", NULL},
    {NULL}};

static PyMethodDef handle_methods[] = {
    {"set_pose", (PyCFunction)(void (*)(void))handle_set_pose, METH_VARARGS | METH_KEYWORDS,
     "set_pose(translate, rotate=(0, 0, 0)) -> None\n\nThe pose reached at the end of the next step (overrides "
     "the path)."},
    {"release", (PyCFunction)handle_release, METH_NOARGS, "release() -> None\n\nLets the vertices go."},
    {"grab", (PyCFunction)handle_grab, METH_VARARGS,
     "grab(vertex=None) -> None\n\nHolds the vertices again where they are; with vertex, a one-vertex handle\n"
     "holds that vertex instead (a mouse pick). InvalidError when not attached to a solver."},
    {NULL}};

PyTypeObject SbpyHandleType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "softbond.Handle",
    .tp_basicsize = sizeof(SbpyHandle),
    .tp_dealloc = (destructor)handle_dealloc,
    .tp_getattro = (getattrofunc)handle_getattro,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "Handle(vertices, /, *, stiffness=0.0, damping=0.0, center=None, path=None, interpolation='linear', "
              "release_time=None, name=None)\n--\n\n"
              "Vertices driven to a moving rigid pose: hard (stiffness 0: by position) or soft (a spring-damper,\n"
              "N/m and N s/m per vertex). path: (time, translate, rotate) keyframes, or set_pose() each step.\n"
              "release_time: s, when the handle lets go (None: never).\n"
              "Pass it to Solver(handles=[...]); attach it to one solver at a time.",
    .tp_methods = handle_methods,
    .tp_getset = handle_getset,
    .tp_init = (initproc)handle_init,
    .tp_new = PyType_GenericNew,
};

/* ---- a scene's own ---- */

/** A tuple of `count` views of the scene's own objects, `view(scene, i)` each. */
static PyObject* scene_views(SbpyScene* scene, uint32_t count, PyObject* (*view)(SbpyScene*, uint32_t)) {
    PyObject* tuple = PyTuple_New(count);
    for (uint32_t i = 0; tuple && i < count; i++) {
        PyObject* item = view(scene, i);
        if (!item) {
            Py_CLEAR(tuple);
            break;
        }
        PyTuple_SET_ITEM(tuple, i, item);
    }
    return tuple;
}

static PyObject* collider_view(SbpyScene* scene, uint32_t i) {
    SbpyCollider* view = (SbpyCollider*)SbpyColliderType.tp_alloc(&SbpyColliderType, 0);
    if (!view) return NULL;
    view->collider = sb_scene_file_solver_def(scene->scene)->colliders[i];
    view->owner = Py_NewRef(scene);
    return (PyObject*)view;
}

static PyObject* handle_view(SbpyScene* scene, uint32_t i) {
    SbpyHandle* view = (SbpyHandle*)SbpyHandleType.tp_alloc(&SbpyHandleType, 0);
    if (!view) return NULL;
    view->handle = sb_scene_file_solver_def(scene->scene)->handles[i];
    view->owner = Py_NewRef(scene);
    return (PyObject*)view;
}

PyObject* sbpy_scene_colliders(SbpyScene* scene) {
    return scene_views(scene, sb_scene_file_solver_def(scene->scene)->collider_count, collider_view);
}

PyObject* sbpy_scene_handles(SbpyScene* scene) {
    return scene_views(scene, sb_scene_file_solver_def(scene->scene)->handle_count, handle_view);
}
