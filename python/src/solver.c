/* softbond.Solver: a model's state advancing in time.
 *
 * advance() releases the GIL for the whole run of steps, so other Python
 * threads (a snapshot reader, a device loop) run meanwhile; a Python
 * callback (external force, on_break, a program's own collider) takes the
 * GIL back for each call and releases it again. An exception a callback
 * raises cannot stop the library's step: it is kept, the callback's
 * contribution is zero from then on, the run stops after the current step
 * and advance() raises it. While an advance runs, every other method of the
 * same solver raises RuntimeError (the library's solver is not to be read
 * or changed by another thread meanwhile: the state buffer is for that). */
#include "sbpy.h"

#include <math.h>

int sbpy_solver_ready(SbpySolver* self) {
    if (!self->solver) {
        PyErr_SetString(PyExc_RuntimeError, "the solver was not created");
        return -1;
    }
    if (self->busy) {
        PyErr_SetString(PyExc_RuntimeError, "the solver is advancing on another thread");
        return -1;
    }
    return 0;
}
#define READY(self)                                                                                                    \
    if (sbpy_solver_ready(self) < 0) return NULL

/* ---- the callbacks ---- */

static void external_force(void* user, uint32_t vertex, double time, const double x[3], const double v[3],
                           double force[3]) {
    SbpySolver* self = user;
    PyGILState_STATE gil = PyGILState_Ensure();
    if (!self->pending.type) {
        PyObject* result = PyObject_CallFunction(self->external_force, "Id(ddd)(ddd)", vertex, time, x[0], x[1], x[2],
                                                 v[0], v[1], v[2]);
        double f[3];
        if (result && (result == Py_None || sbpy_vec3(result, "external_force", "return value", f) == 0)) {
            if (result != Py_None)
                for (int k = 0; k < 3; k++) force[k] += f[k];
        } else {
            sbpy_pending_keep(&self->pending);
        }
        Py_XDECREF(result);
    }
    PyGILState_Release(gil);
}

static void on_break(void* user, uint32_t bond, uint32_t i, uint32_t j, double time) {
    SbpySolver* self = user;
    PyGILState_STATE gil = PyGILState_Ensure();
    if (!self->pending.type) {
        PyObject* result = PyObject_CallFunction(self->on_break, "IIId", bond, i, j, time);
        if (!result) sbpy_pending_keep(&self->pending);
        Py_XDECREF(result);
    }
    PyGILState_Release(gil);
}

/* ---- creation ---- */

/** Every keyword Solver() takes, with where it goes. */
typedef struct solver_options {
    sb_solver_def def;
    const char *integrator, *kernels, *implicit_solver, *wait;
    bool adaptive_threads; /* the scene key's sense: !def.runtime.fixed_width */
    PyObject *colliders, *handles, *blades, *external_force, *on_break;
} solver_options;

static int read_options(solver_options* o, PyObject* kwargs) {
    sb_solver_def* d = &o->def;
    sbpy_option table[] = {
        {"integrator", SBPY_STRING, &o->integrator, NULL},
        {"gravity", SBPY_VEC3, d->gravity, NULL},
        {"drag", SBPY_DOUBLE, &d->drag, NULL},
        {"kernels", SBPY_STRING, &o->kernels, NULL},
        {"threads", SBPY_INT, &d->runtime.threads, NULL},
        {"pin_threads", SBPY_BOOL, &d->runtime.pin, NULL},
        {"wait", SBPY_STRING, &o->wait, NULL},
        {"adaptive_threads", SBPY_BOOL, &o->adaptive_threads, NULL},
        {"colliders", SBPY_OBJECT, &o->colliders, NULL},
        {"contact_thickness", SBPY_DOUBLE, &d->contact_thickness, NULL},
        {"self_collision", SBPY_BOOL, &d->self_collision, NULL},
        {"handles", SBPY_OBJECT, &o->handles, NULL},
        {"blades", SBPY_OBJECT, &o->blades, NULL},
        {"external_force", SBPY_OBJECT, &o->external_force, NULL},
        {"on_break", SBPY_OBJECT, &o->on_break, NULL},
        {"max_splits", SBPY_INT, &d->max_splits, NULL},
        {"max_splits_per_step", SBPY_INT, &d->max_splits_per_step, NULL},
        {"implicit_tolerance", SBPY_DOUBLE, &d->implicit_tolerance, NULL},
        {"implicit_solver", SBPY_STRING, &o->implicit_solver, NULL},
        {"implicit_newton_iterations", SBPY_INT, &d->implicit_newton_iterations, NULL},
        {"implicit_cg_iterations", SBPY_INT, &d->implicit_cg_iterations, NULL},
        {"implicit_definite", SBPY_BOOL, &d->implicit_definite, NULL},
        {"pbd_iterations", SBPY_INT, &d->pbd_iterations, NULL},
        {"vbd_iterations", SBPY_INT, &d->vbd_iterations, NULL},
        {"vbd_chebyshev_rho", SBPY_DOUBLE, &d->vbd_chebyshev_rho, NULL},
        {"vbd_relaxation", SBPY_DOUBLE, &d->vbd_relaxation, NULL},
        {"adaptive", SBPY_BOOL, &d->adaptive, NULL},
        {"min_dt", SBPY_DOUBLE, &d->min_dt, NULL},
        {"adaptive_tolerance", SBPY_DOUBLE, &d->adaptive_tolerance, NULL},
    };
    if (sbpy_options("Solver()", kwargs, table, sizeof table / sizeof table[0]) < 0) return -1;
    d->runtime.fixed_width = !o->adaptive_threads;
    if (o->integrator && !sb_integrator_from_name(o->integrator, &d->integrator)) {
        PyErr_Format(PyExc_ValueError, "Solver(): 'integrator' must be one of softbond.INTEGRATORS, not '%s'",
                     o->integrator);
        return -1;
    }
    if (o->kernels) {
        if (strcmp(o->kernels, "fast") == 0)
            d->kernels = SB_KERNELS_FAST;
        else if (strcmp(o->kernels, "reference") == 0)
            d->kernels = SB_KERNELS_REFERENCE;
        else {
            PyErr_Format(PyExc_ValueError, "Solver(): 'kernels' must be 'fast' or 'reference', not '%s'", o->kernels);
            return -1;
        }
    }
    if (o->wait && !sb_wait_policy_from_name(o->wait, &d->runtime.wait)) {
        PyErr_Format(PyExc_ValueError, "Solver(): 'wait' must be 'spin', 'yield' or 'passive', not '%s'", o->wait);
        return -1;
    }
    if (o->implicit_solver && !sb_linear_solver_from_name(o->implicit_solver, &d->implicit_solver)) {
        PyErr_Format(PyExc_ValueError, "Solver(): 'implicit_solver' must be 'auto', 'cg' or 'cholesky', not '%s'",
                     o->implicit_solver);
        return -1;
    }
    for (PyObject** callback = &o->external_force; callback <= &o->on_break; callback++) {
        if (*callback == Py_None) *callback = NULL;
        if (*callback && !PyCallable_Check(*callback)) {
            PyErr_Format(PyExc_TypeError, "Solver(): '%s' must be callable",
                         callback == &o->on_break ? "on_break" : "external_force");
            return -1;
        }
    }
    return 0;
}

/** A tuple of `type` objects from a sequence (None: empty), naming the keyword. */
static PyObject* typed_tuple(PyObject* seq, PyTypeObject* type, const char* name) {
    if (!seq || seq == Py_None) return PyTuple_New(0);
    PyObject* tuple = PySequence_Tuple(seq);
    if (!tuple) {
        PyErr_Format(PyExc_TypeError, "Solver(): '%s' must be a sequence of %s", name, type->tp_name);
        return NULL;
    }
    for (Py_ssize_t i = 0; i < PyTuple_GET_SIZE(tuple); i++)
        if (!PyObject_TypeCheck(PyTuple_GET_ITEM(tuple, i), type)) {
            PyErr_Format(PyExc_TypeError, "Solver(): %s[%zd] must be a %s, not %s", name, i, type->tp_name,
                         Py_TYPE(PyTuple_GET_ITEM(tuple, i))->tp_name);
            Py_DECREF(tuple);
            return NULL;
        }
    return tuple;
}

/** An attribute of a blade: a mapping's item or an object's attribute (borrowed-like: new ref). */
static PyObject* field(PyObject* obj, const char* name) {
    PyObject* value = PyMapping_Check(obj) && !PySequence_Check(obj) ? PyMapping_GetItemString(obj, name)
                                                                     : PyObject_GetAttrString(obj, name);
    if (!value) PyErr_Clear();
    return value;
}

/** The blades' definitions (PyMem arrays: *defs and each one's path). */
static int read_blades(PyObject* blades, sb_blade_def** defs, uint32_t* count) {
    *defs = NULL;
    *count = 0;
    if (!blades || blades == Py_None) return 0;
    PyObject* seq = PySequence_Fast(blades, "Solver(): 'blades' must be a sequence of softbond.Blade");
    if (!seq) return -1;
    Py_ssize_t n = PySequence_Fast_GET_SIZE(seq);
    *defs = PyMem_Calloc(n ? (size_t)n : 1, sizeof **defs);
    if (!*defs) {
        Py_DECREF(seq);
        PyErr_NoMemory();
        return -1;
    }
    int status = 0;
    for (Py_ssize_t i = 0; i < n && status == 0; i++) {
        PyObject* blade = PySequence_Fast_GET_ITEM(seq, i);
        PyObject *a = field(blade, "a"), *b = field(blade, "b"), *path = field(blade, "path"),
                 *interpolation = field(blade, "interpolation");
        sb_blade_def* def = &(*defs)[i];
        *count = (uint32_t)i + 1;
        const char* mode = interpolation && PyUnicode_Check(interpolation) ? PyUnicode_AsUTF8(interpolation) : NULL;
        if (!a || !b) {
            PyErr_Format(PyExc_TypeError, "Solver(): blades[%zd] needs 'a' and 'b' (softbond.Blade)", i);
            status = -1;
        } else if (sbpy_vec3(a, "Solver()", "blades[].a", def->a) < 0 ||
                   sbpy_vec3(b, "Solver()", "blades[].b", def->b) < 0 ||
                   sbpy_keyframes(path, "Solver(): blades[]", (sb_keyframe**)&def->path, &def->path_count) < 0 ||
                   sbpy_interpolation(mode, "Solver(): blades[]", &def->interpolation) < 0) {
            status = -1;
        }
        Py_XDECREF(a);
        Py_XDECREF(b);
        Py_XDECREF(path);
        Py_XDECREF(interpolation);
    }
    Py_DECREF(seq);
    return status;
}

static void free_blades(sb_blade_def* defs, uint32_t count) {
    for (uint32_t i = 0; defs && i < count; i++) PyMem_Free((void*)defs[i].path);
    PyMem_Free(defs);
}

/** Points the definition at the colliders' and handles' library objects. */
static int attach(SbpySolver* self, sb_solver_def* def) {
    Py_ssize_t nc = PyTuple_GET_SIZE(self->colliders), nh = PyTuple_GET_SIZE(self->handles);
    self->collider_ptrs = PyMem_Calloc(nc ? (size_t)nc : 1, sizeof *self->collider_ptrs);
    self->handle_ptrs = PyMem_Calloc(nh ? (size_t)nh : 1, sizeof *self->handle_ptrs);
    if (!self->collider_ptrs || !self->handle_ptrs) {
        PyErr_NoMemory();
        return -1;
    }
    for (Py_ssize_t i = 0; i < nc; i++)
        self->collider_ptrs[i] = ((SbpyCollider*)PyTuple_GET_ITEM(self->colliders, i))->collider;
    for (Py_ssize_t i = 0; i < nh; i++)
        self->handle_ptrs[i] = ((SbpyHandle*)PyTuple_GET_ITEM(self->handles, i))->handle;
    for (Py_ssize_t i = 0; i < nc + nh; i++)
        if (i < nc ? !self->collider_ptrs[i] : !self->handle_ptrs[i - nc]) {
            PyErr_Format(PyExc_ValueError, "Solver(): %s[%zd] was not initialized", i < nc ? "colliders" : "handles",
                         i < nc ? i : i - nc);
            return -1;
        }
    def->colliders = self->collider_ptrs;
    def->collider_count = (uint32_t)nc;
    def->handles = self->handle_ptrs;
    def->handle_count = (uint32_t)nh;
    return 0;
}

static int solver_init(SbpySolver* self, PyObject* args, PyObject* kwargs) {
    PyObject* source;
    if (self->solver) {
        PyErr_SetString(PyExc_RuntimeError, "Solver(): already created");
        return -1;
    }
    if (!PyArg_ParseTuple(args, "O:Solver", &source)) return -1;
    solver_options o = {.def = sb_default_solver_def()};
    bool from_scene = PyObject_TypeCheck(source, &SbpySceneType);
    if (from_scene) {
        SbpyScene* scene = (SbpyScene*)source;
        o.def = *sb_scene_file_solver_def(scene->scene);
        self->scene = Py_NewRef(source);
        self->model = sbpy_model_wrap((sb_model*)sb_scene_file_model(scene->scene), source);
        if (!self->model) return -1;
    } else if (PyObject_TypeCheck(source, &SbpyModelType)) {
        self->model = Py_NewRef(source);
    } else {
        PyErr_Format(PyExc_TypeError, "Solver(): 'model' must be a softbond.Model or softbond.Scene, not %s",
                     Py_TYPE(source)->tp_name);
        return -1;
    }
    o.adaptive_threads = !o.def.runtime.fixed_width;
    if (read_options(&o, kwargs) < 0) return -1;
    if (from_scene) {
        /* the scene's own colliders and handles, unless the keywords replace them */
        self->colliders = o.colliders ? NULL : sbpy_scene_colliders((SbpyScene*)source);
        self->handles = o.handles ? NULL : sbpy_scene_handles((SbpyScene*)source);
        if (PyErr_Occurred()) return -1;
    }
    if (!self->colliders) self->colliders = typed_tuple(o.colliders, &SbpyColliderType, "colliders");
    if (self->colliders && !self->handles) self->handles = typed_tuple(o.handles, &SbpyHandleType, "handles");
    if (!self->colliders || !self->handles) return -1;
    sb_blade_def* blades = NULL;
    uint32_t blade_count = 0;
    if (read_blades(o.blades, &blades, &blade_count) < 0) {
        free_blades(blades, blade_count);
        return -1;
    }
    if (attach(self, &o.def) < 0) {
        free_blades(blades, blade_count);
        return -1;
    }
    if (o.blades) o.def.blades = blades, o.def.blade_count = blade_count;
    if (o.external_force) {
        self->external_force = Py_NewRef(o.external_force);
        o.def.external_force = external_force;
        o.def.external_user = self;
    }
    if (o.on_break) {
        self->on_break = Py_NewRef(o.on_break);
        o.def.on_break = on_break;
        o.def.break_user = self;
    }
    sb_error err = {{0}};
    const sb_model* model = ((SbpyModel*)self->model)->model;
    Py_BEGIN_ALLOW_THREADS self->solver = sb_solver_create(model, &o.def, &err);
    Py_END_ALLOW_THREADS free_blades(blades, blade_count);
    if (!self->solver) {
        sbpy_raise(SB_ERR_INVALID, err.message);
        return -1;
    }
    return 0;
}

/** Destroys the library's solver first (it points at the colliders and handles), then drops the references. */
static int solver_clear(SbpySolver* self) {
    if (self->solver) {
        sb_solver* solver = self->solver;
        self->solver = NULL;
        Py_BEGIN_ALLOW_THREADS sb_solver_destroy(solver);
        Py_END_ALLOW_THREADS
    }
    Py_CLEAR(self->pending.type);
    Py_CLEAR(self->pending.value);
    Py_CLEAR(self->pending.traceback);
    Py_CLEAR(self->external_force);
    Py_CLEAR(self->on_break);
    Py_CLEAR(self->colliders);
    Py_CLEAR(self->handles);
    Py_CLEAR(self->scene);
    Py_CLEAR(self->model);
    return 0;
}

static void solver_dealloc(SbpySolver* self) {
    PyObject_GC_UnTrack(self);
    solver_clear(self);
    PyMem_Free(self->collider_ptrs);
    PyMem_Free(self->handle_ptrs);
    Py_TYPE(self)->tp_free((PyObject*)self);
}

static int solver_traverse(SbpySolver* self, visitproc visit, void* arg) {
    Py_VISIT(self->external_force);
    Py_VISIT(self->on_break);
    Py_VISIT(self->colliders);
    Py_VISIT(self->handles);
    return 0;
}

/* ---- advancing ---- */

/** Raises the first exception a callback kept during the run: -1, else 0. */
static int raise_callback_error(SbpySolver* self) {
    if (sbpy_pending_raise(&self->pending) < 0) return -1;
    for (Py_ssize_t i = 0; i < PyTuple_GET_SIZE(self->colliders); i++)
        if (sbpy_pending_raise(&((SbpyCollider*)PyTuple_GET_ITEM(self->colliders, i))->pending) < 0) return -1;
    return 0;
}

static bool callback_failed(SbpySolver* self) {
    if (__atomic_load_n(&self->pending.type, __ATOMIC_ACQUIRE)) return true;
    for (Py_ssize_t i = 0; i < PyTuple_GET_SIZE(self->colliders); i++)
        if (__atomic_load_n(&((SbpyCollider*)PyTuple_GET_ITEM(self->colliders, i))->pending.type, __ATOMIC_ACQUIRE))
            return true;
    return false;
}

static PyObject* solver_advance(SbpySolver* self, PyObject* args, PyObject* kwargs) {
    static char* keywords[] = {"dt", "steps", "publish", NULL};
    double dt;
    Py_ssize_t steps = 1;
    PyObject* publish = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "d|$nO:advance", keywords, &dt, &steps, &publish)) return NULL;
    READY(self);
    if (!(dt > 0) || !isfinite(dt)) return PyErr_Format(PyExc_ValueError, "advance(): 'dt' must be > 0 and finite");
    if (steps < 0) return PyErr_Format(PyExc_ValueError, "advance(): 'steps' must be >= 0 (got %zd)", steps);
    sb_state_buffer* buffer = NULL;
    if (publish != Py_None) {
        if (!PyObject_TypeCheck(publish, &SbpyStateBufferType))
            return PyErr_Format(PyExc_TypeError, "advance(): 'publish' must be a softbond.StateBuffer, not %s",
                                Py_TYPE(publish)->tp_name);
        buffer = ((SbpyStateBuffer*)publish)->buffer;
    }
    Py_INCREF(publish);
    uint64_t steps_before = sb_solver_step_count(self->solver);
    bool watch = self->external_force || self->on_break || PyTuple_GET_SIZE(self->colliders);
    sb_status status = SB_OK;
    self->busy = 1;
    Py_BEGIN_ALLOW_THREADS for (Py_ssize_t i = 0; i < steps && status == SB_OK; i++) {
        status = buffer ? sb_solver_advance_published(self->solver, dt, buffer) : sb_solver_advance(self->solver, dt);
        if (watch && callback_failed(self)) break;
    }
    Py_END_ALLOW_THREADS self->busy = 0;
    Py_DECREF(publish);
    if (raise_callback_error(self) < 0) return NULL;
    if (status == SB_ERR_INVALID && buffer && self->solver && sb_solver_step_count(self->solver) == steps_before)
        return sbpy_raise(status, "advance(): 'publish' is a StateBuffer of another solver (its vertex count differs)");
    if (status != SB_OK) {
        const char* message = sb_solver_error(self->solver);
        return sbpy_raise(status, message[0] ? message : sb_status_name(status));
    }
    Py_RETURN_NONE;
}

/* ---- the state ---- */

/** n = the solver's vertex count. */
static npy_intp vertices(SbpySolver* self) { return sb_solver_vertex_count(self->solver); }

/** out: a writable C-contiguous (n, 3) float64 array, else TypeError/ValueError naming it. */
static int check_out(PyObject* out, npy_intp n, const char* function) {
    if (!PyArray_Check(out)) {
        PyErr_Format(PyExc_TypeError, "%s: 'out' must be a numpy.ndarray, not %s", function, Py_TYPE(out)->tp_name);
        return -1;
    }
    PyArrayObject* a = (PyArrayObject*)out;
    if (PyArray_TYPE(a) != NPY_DOUBLE || !PyArray_IS_C_CONTIGUOUS(a) || !PyArray_ISWRITEABLE(a) ||
        PyArray_NDIM(a) != 2 || PyArray_DIM(a, 0) != n || PyArray_DIM(a, 1) != 3) {
        PyErr_Format(PyExc_ValueError, "%s: 'out' must be a writable C-contiguous float64 array of shape (%zd, 3)",
                     function, (Py_ssize_t)n);
        return -1;
    }
    return 0;
}

typedef void (*state_getter)(const sb_solver*, double*);

static PyObject* copy_state(SbpySolver* self, PyObject* out, state_getter get, const char* function) {
    READY(self);
    npy_intp n = vertices(self);
    if (out && out != Py_None) {
        if (check_out(out, n, function) < 0) return NULL;
        get(self->solver, PyArray_DATA((PyArrayObject*)out));
        return Py_NewRef(out);
    }
    npy_intp dims[2] = {n, 3};
    PyObject* array = PyArray_SimpleNew(2, dims, NPY_DOUBLE);
    if (array) get(self->solver, PyArray_DATA((PyArrayObject*)array));
    return array;
}

static PyObject* solver_get_positions(SbpySolver* self, PyObject* args) {
    PyObject* out = NULL;
    if (!PyArg_ParseTuple(args, "|O:get_positions", &out)) return NULL;
    return copy_state(self, out, sb_solver_get_positions, "get_positions()");
}
static PyObject* solver_get_velocities(SbpySolver* self, PyObject* args) {
    PyObject* out = NULL;
    if (!PyArg_ParseTuple(args, "|O:get_velocities", &out)) return NULL;
    return copy_state(self, out, sb_solver_get_velocities, "get_velocities()");
}
static PyObject* solver_get_forces(SbpySolver* self, PyObject* args) {
    PyObject* out = NULL;
    if (!PyArg_ParseTuple(args, "|O:get_forces", &out)) return NULL;
    return copy_state(self, out, sb_solver_get_forces, "get_forces()");
}
static PyObject* solver_positions(SbpySolver* self, void* closure) {
    (void)closure;
    return copy_state(self, NULL, sb_solver_get_positions, "positions");
}
static PyObject* solver_velocities(SbpySolver* self, void* closure) {
    (void)closure;
    return copy_state(self, NULL, sb_solver_get_velocities, "velocities");
}
static PyObject* solver_forces(SbpySolver* self, void* closure) {
    (void)closure;
    return copy_state(self, NULL, sb_solver_get_forces, "forces");
}

static PyObject* solver_set_state(SbpySolver* self, PyObject* args, PyObject* kwargs) {
    static char* keywords[] = {"positions", "velocities", NULL};
    PyObject *positions, *velocities = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O|O:set_state", keywords, &positions, &velocities)) return NULL;
    READY(self);
    npy_intp n = vertices(self);
    PyArrayObject* x = sbpy_array(positions, "set_state()", "positions", NPY_DOUBLE, 3);
    PyArrayObject* v =
        x && velocities != Py_None ? sbpy_array(velocities, "set_state()", "velocities", NPY_DOUBLE, 3) : NULL;
    if (!x || (velocities != Py_None && !v)) goto fail;
    if (PyArray_DIM(x, 0) != n || (v && PyArray_DIM(v, 0) != n)) {
        PyErr_Format(PyExc_ValueError, "set_state(): 'positions' and 'velocities' must have %zd rows", (Py_ssize_t)n);
        goto fail;
    }
    sb_status status = sb_solver_set_state(self->solver, PyArray_DATA(x), v ? PyArray_DATA(v) : NULL);
    Py_DECREF(x);
    Py_XDECREF(v);
    if (status != SB_OK) return sbpy_raise(status, sb_solver_error(self->solver));
    Py_RETURN_NONE;
fail:
    Py_XDECREF(x);
    Py_XDECREF(v);
    return NULL;
}

static PyObject* solver_set_gravity(SbpySolver* self, PyObject* arg) {
    double g[3];
    if (sbpy_vec3(arg, "set_gravity()", "gravity", g) < 0) return NULL;
    READY(self);
    if (sb_solver_set_gravity(self->solver, g) != SB_OK)
        return PyErr_Format(PyExc_ValueError, "set_gravity(): 'gravity' must be finite");
    Py_RETURN_NONE;
}

/* ---- energies, statistics, forces on tools ---- */

static PyObject* solver_energies(SbpySolver* self, PyObject* unused) {
    (void)unused;
    READY(self);
    sb_energies e = sb_solver_energies(self->solver);
    PyObject* dict = PyDict_New();
    for (int t = 0; dict && t < SB_TERM_COUNT; t++) {
        PyObject* value = PyFloat_FromDouble(e.term[t]);
        if (!value || PyDict_SetItemString(dict, sb_term_name((sb_term)t), value) < 0) Py_CLEAR(dict);
        Py_XDECREF(value);
    }
    const char* names[] = {"kinetic", "gravity", "internal", "total"};
    double values[] = {e.kinetic, e.gravity, sb_energies_internal(&e), sb_energies_total(&e)};
    for (int k = 0; dict && k < 4; k++) {
        PyObject* value = PyFloat_FromDouble(values[k]);
        if (!value || PyDict_SetItemString(dict, names[k], value) < 0) Py_CLEAR(dict);
        Py_XDECREF(value);
    }
    return dict;
}

static PyObject* solver_last_step(SbpySolver* self, void* closure) {
    (void)closure;
    READY(self);
    sb_step_stats s = sb_solver_last_step(self->solver);
    return Py_BuildValue("{s:i,s:i,s:O,s:I,s:I,s:I,s:I,s:I,s:I,s:I,s:d,s:d}", "newton_iterations", s.newton_iterations,
                         "cg_iterations", s.cg_iterations, "converged", s.converged ? Py_True : Py_False,
                         "cg_indefinite", s.cg_indefinite, "factorizations", s.factorizations, "substeps", s.substeps,
                         "rejected", s.rejected, "contacts", s.contacts, "self_contacts", s.self_contacts,
                         "self_dropped", s.self_dropped, "last_substep", s.last_substep, "min_substep", s.min_substep);
}

static PyObject* solver_contact_force(SbpySolver* self, PyObject* arg) {
    READY(self);
    Py_ssize_t index = -1, count = PyTuple_GET_SIZE(self->colliders);
    if (PyObject_TypeCheck(arg, &SbpyColliderType)) {
        /* by the library's collider, so that any view of a scene's collider finds it */
        for (Py_ssize_t i = 0; i < count; i++)
            if (((SbpyCollider*)PyTuple_GET_ITEM(self->colliders, i))->collider == ((SbpyCollider*)arg)->collider)
                index = i;
        if (index < 0) return PyErr_Format(PyExc_ValueError, "contact_force(): the collider is not this solver's");
    } else {
        index = PyNumber_AsSsize_t(arg, PyExc_IndexError);
        if (index == -1 && PyErr_Occurred()) return NULL;
        if (index < 0 || index >= count)
            return PyErr_Format(PyExc_IndexError, "contact_force(): 'index' %zd is not below %zd", index, count);
    }
    double force[3];
    sb_solver_contact_force(self->solver, (uint32_t)index, force);
    return sbpy_vector3(force);
}

/* ---- checkpoints ---- */

static PyObject* solver_save_state(SbpySolver* self, PyObject* unused) {
    (void)unused;
    READY(self);
    size_t size = sb_solver_state_size(self->solver);
    PyObject* bytes = PyBytes_FromStringAndSize(NULL, (Py_ssize_t)size);
    if (!bytes) return NULL;
    sb_error err = {{0}};
    sb_status status = sb_solver_save_state(self->solver, PyBytes_AS_STRING(bytes), size, &err);
    if (status != SB_OK) {
        Py_DECREF(bytes);
        return sbpy_raise(status, err.message);
    }
    return bytes;
}

static PyObject* solver_load_state(SbpySolver* self, PyObject* args) {
    Py_buffer data;
    if (!PyArg_ParseTuple(args, "y*:load_state", &data)) return NULL;
    if (sbpy_solver_ready(self) < 0) {
        PyBuffer_Release(&data);
        return NULL;
    }
    sb_error err = {{0}};
    sb_status status = sb_solver_load_state(self->solver, data.buf, (size_t)data.len, &err);
    PyBuffer_Release(&data);
    if (status != SB_OK) return sbpy_raise(status, err.message);
    Py_RETURN_NONE;
}

/* ---- breakage and tearing ---- */

static PyObject* solver_broken_bonds(SbpySolver* self, void* closure) {
    (void)closure;
    READY(self);
    const sb_model* model = ((SbpyModel*)self->model)->model;
    npy_intp count = sb_solver_broken_count(self->solver), k = 0;
    PyObject* array = PyArray_SimpleNew(1, &count, NPY_UINT32);
    if (!array) return NULL;
    uint32_t* out = PyArray_DATA((PyArrayObject*)array);
    for (uint32_t b = 0; b < sb_model_bond_count(model) && k < count; b++)
        if (sb_solver_bond_broken(self->solver, b)) out[k++] = b;
    return array;
}

static PyObject* solver_triangles(SbpySolver* self, void* closure) {
    (void)closure;
    READY(self);
    npy_intp dims[2] = {sb_model_triangle_count(((SbpyModel*)self->model)->model), 3};
    PyObject* array = PyArray_SimpleNew(2, dims, NPY_UINT32);
    if (!array) return NULL;
    uint32_t* out = PyArray_DATA((PyArrayObject*)array);
    for (npy_intp t = 0; t < dims[0]; t++) sb_solver_triangle(self->solver, (uint32_t)t, out + 3 * t);
    return array;
}

static PyObject* solver_triangles_alive(SbpySolver* self, void* closure) {
    (void)closure;
    READY(self);
    npy_intp n = sb_model_triangle_count(((SbpyModel*)self->model)->model);
    PyObject* array = PyArray_SimpleNew(1, &n, NPY_BOOL);
    if (!array) return NULL;
    npy_bool* out = PyArray_DATA((PyArrayObject*)array);
    for (npy_intp t = 0; t < n; t++) out[t] = sb_solver_triangle_alive(self->solver, (uint32_t)t);
    return array;
}

static PyObject* solver_vertex_origins(SbpySolver* self, void* closure) {
    (void)closure;
    READY(self);
    npy_intp n = vertices(self);
    PyObject* array = PyArray_SimpleNew(1, &n, NPY_UINT32);
    if (!array) return NULL;
    uint32_t* out = PyArray_DATA((PyArrayObject*)array);
    for (npy_intp v = 0; v < n; v++) out[v] = sb_solver_vertex_origin(self->solver, (uint32_t)v);
    return array;
}

/* ---- small getters ---- */

static PyObject* solver_time(SbpySolver* self, void* closure) {
    (void)closure;
    READY(self);
    return PyFloat_FromDouble(sb_solver_time(self->solver));
}
static PyObject* solver_step_count(SbpySolver* self, void* closure) {
    (void)closure;
    READY(self);
    return PyLong_FromUnsignedLongLong(sb_solver_step_count(self->solver));
}
static PyObject* solver_vertex_count(SbpySolver* self, void* closure) {
    (void)closure;
    READY(self);
    return PyLong_FromSsize_t(vertices(self));
}
static PyObject* solver_vertex_capacity(SbpySolver* self, void* closure) {
    (void)closure;
    READY(self);
    return PyLong_FromUnsignedLong(sb_solver_vertex_capacity(self->solver));
}
static PyObject* solver_model(SbpySolver* self, void* closure) {
    (void)closure;
    return Py_NewRef(self->model ? self->model : Py_None);
}
static PyObject* solver_colliders(SbpySolver* self, void* closure) {
    (void)closure;
    return Py_NewRef(self->colliders ? self->colliders : Py_None);
}
static PyObject* solver_handles(SbpySolver* self, void* closure) {
    (void)closure;
    return Py_NewRef(self->handles ? self->handles : Py_None);
}

static PyGetSetDef solver_getset[] = {
    {"positions", (getter)solver_positions, NULL,
     "Positions, m: a new (n, 3) float64 array (a copy; get_positions(out) fills your own).", NULL},
    {"velocities", (getter)solver_velocities, NULL, "Velocities, m/s: a new (n, 3) float64 array (a copy).", NULL},
    {"forces", (getter)solver_forces, NULL,
     "Total forces (internal, gravity, drag, external) at the current state, N: a new (n, 3) array.", NULL},
    {"time", (getter)solver_time, NULL, "Simulated time, s.", NULL},
    {"step_count", (getter)solver_step_count, NULL, "Advances so far (a failed one included).", NULL},
    {"vertex_count", (getter)solver_vertex_count, NULL, "Vertices now (a tearing solver's copies included).", NULL},
    {"vertex_capacity", (getter)solver_vertex_capacity, NULL,
     "The most vertices the solver can have (size a StateBuffer by it).", NULL},
    {"vertex_origins", (getter)solver_vertex_origins, NULL, "Each vertex's model vertex: (n,) uint32.", NULL},
    {"triangles", (getter)solver_triangles, NULL, "The triangles' current corners (tearing renumbers): (t, 3).", NULL},
    {"triangles_alive", (getter)solver_triangles_alive, NULL, "Which triangles have no broken bond: (t,) bool.", NULL},
    {"broken_bonds", (getter)solver_broken_bonds, NULL, "The bonds broken or cut so far, ascending: uint32 array.",
     NULL},
    {"last_step", (getter)solver_last_step, NULL,
     "What the last advance did (a dict: substeps, rejected, contacts, newton_iterations, ...).", NULL},
    {"model", (getter)solver_model, NULL, "The Model it advances.", NULL},
    {"colliders", (getter)solver_colliders, NULL, "The Collider objects given (a tuple).", NULL},
    {"handles", (getter)solver_handles, NULL, "The Handle objects given (a tuple).", NULL},
    {NULL}};

static PyMethodDef solver_methods[] = {
    {"advance", (PyCFunction)(void (*)(void))solver_advance, METH_VARARGS | METH_KEYWORDS,
     "advance(dt, *, steps=1, publish=None) -> None\n\n"
     "Advances by `steps` steps of dt seconds with the GIL released (other Python threads run meanwhile).\n"
     "publish: a StateBuffer that receives a snapshot after every step. A failing step raises the\n"
     "softbond.Error subclass of its status with the library's message (the state is then undefined);\n"
     "an exception raised by a callback stops the run after that step and is raised here."},
    {"get_positions", (PyCFunction)solver_get_positions, METH_VARARGS,
     "get_positions(out=None) -> ndarray\n\nPositions (m) into out, a C-contiguous (n, 3) float64 array (no\n"
     "allocation), or into a new array; returns it."},
    {"get_velocities", (PyCFunction)solver_get_velocities, METH_VARARGS,
     "get_velocities(out=None) -> ndarray\n\nVelocities (m/s), as get_positions."},
    {"get_forces", (PyCFunction)solver_get_forces, METH_VARARGS,
     "get_forces(out=None) -> ndarray\n\nTotal forces (N) at the current state, as get_positions."},
    {"set_state", (PyCFunction)(void (*)(void))solver_set_state, METH_VARARGS | METH_KEYWORDS,
     "set_state(positions, velocities=None) -> None\n\nReplaces the state ((n, 3) arrays; velocities None = 0);\n"
     "fixed vertices keep their rest positions."},
    {"set_gravity", (PyCFunction)solver_set_gravity, METH_O,
     "set_gravity(gravity) -> None\n\nChanges gravity (m/s^2) from the next step on."},
    {"energies", (PyCFunction)solver_energies, METH_NOARGS,
     "energies() -> dict\n\nThe state's energies, J: one entry per term of softbond.TERMS, 'kinetic', 'gravity',\n"
     "'internal' (the terms' sum) and 'total'."},
    {"contact_force", (PyCFunction)solver_contact_force, METH_O,
     "contact_force(collider) -> ndarray\n\nThe force (N, shape (1, 3)) a collider (the object or its index)\n"
     "received from the bodies during the last advance."},
    {"save_state", (PyCFunction)solver_save_state, METH_NOARGS,
     "save_state() -> bytes\n\nA checkpoint: the whole state, from which a run continues bitwise."},
    {"load_state", (PyCFunction)solver_load_state, METH_VARARGS,
     "load_state(data) -> None\n\nReads a checkpoint (bytes-like) into a solver made as the saving one was;\n"
     "InvalidError (the solver unchanged) for a corrupt one or another model's or precision's."},
    {NULL}};

PyTypeObject SbpySolverType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "softbond.Solver",
    .tp_basicsize = sizeof(SbpySolver),
    .tp_dealloc = (destructor)solver_dealloc,
    .tp_traverse = (traverseproc)solver_traverse,
    .tp_clear = (inquiry)solver_clear,
    .tp_flags = Py_TPFLAGS_DEFAULT | Py_TPFLAGS_HAVE_GC,
    .tp_doc = "Solver(model, /, **options)\n--\n\n"
              "A model's state advancing in time. model: a Model, or a Scene (its model and its solver definition:\n"
              "integrator, gravity, colliders, handles, blades, point load; keywords override them).\n\n"
              "Options: integrator (softbond.INTEGRATORS, default 'verlet'), gravity (m/s^2, default (0, 0, -9.81)),\n"
              "drag (1/s), kernels ('fast' or 'reference'), threads (0 = SOFTBOND_THREADS or one per processor),\n"
              "pin_threads, wait ('passive', 'yield' or 'spin': how idle team threads wait), adaptive_threads\n"
              "(default True: a step may run on one thread while that measures faster), colliders (Collider\n"
              "list), contact_thickness (m), self_collision, handles (Handle list),\n"
              "blades (Blade list), external_force (callable(vertex, time, position, velocity) -> force or None,\n"
              "called per free vertex per force evaluation), on_break (callable(bond, i, j, time)), max_splits,\n"
              "max_splits_per_step, implicit_tolerance, implicit_solver ('auto', 'cg', 'cholesky'),\n"
              "implicit_newton_iterations, implicit_cg_iterations, implicit_definite, pbd_iterations,\n"
              "vbd_iterations, vbd_chebyshev_rho, vbd_relaxation, adaptive, min_dt (s), adaptive_tolerance.\n\n"
              "The solver keeps its model, colliders and handles alive. Methods other than advance must be called\n"
              "while no advance runs (RuntimeError otherwise); read a running solver from other threads through a\n"
              "StateBuffer.",
    .tp_methods = solver_methods,
    .tp_getset = solver_getset,
    .tp_init = (initproc)solver_init,
    .tp_new = PyType_GenericNew,
};
