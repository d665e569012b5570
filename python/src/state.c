/* softbond.StateBuffer and softbond.Snapshot: reading a running solver
 * from other threads. The thread that advances publishes (advance(...,
 * publish=buffer) or Solver.publish); any thread acquires the latest
 * snapshot, lock-free, and reads its positions and velocities as read-only
 * NumPy views of the snapshot's own memory (no copy), in the state's
 * precision (softbond.REAL_DTYPE). A snapshot is held until released (or
 * its with-block ends, or it is garbage); the writer does not touch it
 * meanwhile. Its views stay valid memory as long as they live (they keep
 * the snapshot and the buffer alive), but after the release the writer may
 * reuse the slot: copy what you keep. */
#include "sbpy.h"

static int buffer_init(SbpyStateBuffer* self, PyObject* args, PyObject* kwargs) {
    static char* keywords[] = {"solver", "max_readers", NULL};
    PyObject* solver;
    int max_readers = 1;
    if (self->buffer) {
        PyErr_SetString(PyExc_RuntimeError, "StateBuffer(): already created");
        return -1;
    }
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O!|i:StateBuffer", keywords, &SbpySolverType, &solver,
                                     &max_readers))
        return -1;
    if (max_readers < 1) {
        PyErr_Format(PyExc_ValueError, "StateBuffer(): 'max_readers' must be >= 1 (got %d)", max_readers);
        return -1;
    }
    if (sbpy_solver_ready((SbpySolver*)solver) < 0) return -1;
    self->capacity = sb_solver_vertex_capacity(((SbpySolver*)solver)->solver);
    sb_error err = {{0}};
    self->buffer = sb_state_buffer_create(self->capacity, max_readers, &err);
    if (!self->buffer) {
        sbpy_raise(SB_ERR_NOMEM, err.message);
        return -1;
    }
    return 0;
}

static void buffer_dealloc(SbpyStateBuffer* self) {
    sb_state_buffer_destroy(self->buffer);
    Py_TYPE(self)->tp_free((PyObject*)self);
}

/** softbond.Snapshot: one held snapshot. */
typedef struct SbpySnapshot {
    PyObject_HEAD SbpyStateBuffer* owner;
    const sb_snapshot* snapshot; /**< NULL once released */
    const sb_snapshot* data;     /**< the slot, readable while owner lives */
} SbpySnapshot;

static PyObject* buffer_acquire(SbpyStateBuffer* self, PyObject* unused) {
    (void)unused;
    const sb_snapshot* snapshot = sb_state_buffer_acquire(self->buffer);
    if (!snapshot) Py_RETURN_NONE;
    SbpySnapshot* held = PyObject_New(SbpySnapshot, &SbpySnapshotType);
    if (!held) {
        sb_state_buffer_release(self->buffer, snapshot);
        return NULL;
    }
    held->owner = (SbpyStateBuffer*)Py_NewRef(self);
    held->snapshot = held->data = snapshot;
    return (PyObject*)held;
}

static PyObject* buffer_published(SbpyStateBuffer* self, void* closure) {
    (void)closure;
    return PyLong_FromUnsignedLongLong(sb_state_buffer_published(self->buffer));
}
static PyObject* buffer_skipped(SbpyStateBuffer* self, void* closure) {
    (void)closure;
    return PyLong_FromUnsignedLongLong(sb_state_buffer_skipped(self->buffer));
}

static PyObject* buffer_publish(SbpyStateBuffer* self, PyObject* solver) {
    if (!PyObject_TypeCheck(solver, &SbpySolverType))
        return PyErr_Format(PyExc_TypeError, "publish(): 'solver' must be a softbond.Solver");
    if (sbpy_solver_ready((SbpySolver*)solver) < 0) return NULL;
    sb_status status = sb_solver_publish(((SbpySolver*)solver)->solver, self->buffer);
    if (status != SB_OK)
        return sbpy_raise(status, status == SB_ERR_BUSY ? "publish(): every slot is held by a reader"
                                                        : "publish(): the buffer was made for another solver");
    Py_RETURN_NONE;
}

/** Refused before __init__ (no library buffer yet). */
static PyObject* buffer_getattro(SbpyStateBuffer* self, PyObject* name) {
    if (!self->buffer) return PyErr_Format(PyExc_RuntimeError, "the StateBuffer was not initialized");
    return PyObject_GenericGetAttr((PyObject*)self, name);
}

static PyGetSetDef buffer_getset[] = {
    {"published", (getter)buffer_published, NULL, "Snapshots committed so far.", NULL},
    {"skipped", (getter)buffer_skipped, NULL, "Publications skipped because every slot was held.", NULL},
    {NULL}};

static PyMethodDef buffer_methods[] = {
    {"acquire", (PyCFunction)buffer_acquire, METH_NOARGS,
     "acquire() -> Snapshot | None\n\nThe latest snapshot, held until released (use it in a with-block), or None\n"
     "before the first publication. Any thread; lock-free."},
    {"publish", (PyCFunction)buffer_publish, METH_O,
     "publish(solver) -> None\n\nPublishes the solver's current state (the advancing thread, between advances)."},
    {NULL}};

PyTypeObject SbpyStateBufferType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "softbond.StateBuffer",
    .tp_basicsize = sizeof(SbpyStateBuffer),
    .tp_dealloc = (destructor)buffer_dealloc,
    .tp_getattro = (getattrofunc)buffer_getattro,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "StateBuffer(solver, max_readers=1)\n--\n\n"
              "Snapshots of a solver's state for other threads: the advancing thread publishes (advance(dt,\n"
              "publish=buffer)), up to max_readers threads each hold one snapshot at a time (acquire()). The writer\n"
              "never waits for a reader.",
    .tp_methods = buffer_methods,
    .tp_getset = buffer_getset,
    .tp_init = (initproc)buffer_init,
    .tp_new = PyType_GenericNew,
};

/* ---- Snapshot ---- */

static void snapshot_release_now(SbpySnapshot* self) {
    if (self->snapshot) sb_state_buffer_release(self->owner->buffer, self->snapshot);
    self->snapshot = NULL;
}

static void snapshot_dealloc(SbpySnapshot* self) {
    snapshot_release_now(self);
    Py_XDECREF(self->owner);
    PyObject_Free(self);
}

static PyObject* snapshot_release(SbpySnapshot* self, PyObject* unused) {
    (void)unused;
    snapshot_release_now(self);
    Py_RETURN_NONE;
}

static PyObject* snapshot_enter(SbpySnapshot* self, PyObject* unused) {
    (void)unused;
    return Py_NewRef(self);
}

static PyObject* snapshot_exit(SbpySnapshot* self, PyObject* args) {
    (void)args;
    snapshot_release_now(self);
    Py_RETURN_FALSE;
}

/** A read-only (n, 3) view of one of the snapshot's arrays, keeping the snapshot alive. */
static PyObject* view(SbpySnapshot* self, sb_real* data) {
    if (!self->snapshot) {
        PyErr_SetString(PyExc_RuntimeError, "the snapshot was released: acquire a new one");
        return NULL;
    }
    npy_intp dims[2] = {self->data->vertex_count, 3};
    PyObject* array = PyArray_New(&PyArray_Type, 2, dims, SBPY_NPY_REAL, NULL, data, 0, NPY_ARRAY_C_CONTIGUOUS, NULL);
    if (!array) return NULL;
    if (PyArray_SetBaseObject((PyArrayObject*)array, Py_NewRef(self)) < 0) {
        Py_DECREF(array);
        return NULL;
    }
    return array;
}

static PyObject* snapshot_positions(SbpySnapshot* self, void* closure) {
    (void)closure;
    return view(self, self->data->positions);
}
static PyObject* snapshot_velocities(SbpySnapshot* self, void* closure) {
    (void)closure;
    return view(self, self->data->velocities);
}
static PyObject* snapshot_sequence(SbpySnapshot* self, void* closure) {
    (void)closure;
    return PyLong_FromUnsignedLongLong(self->data->sequence);
}
static PyObject* snapshot_step(SbpySnapshot* self, void* closure) {
    (void)closure;
    return PyLong_FromUnsignedLongLong(self->data->step);
}
static PyObject* snapshot_time(SbpySnapshot* self, void* closure) {
    (void)closure;
    return PyFloat_FromDouble(self->data->time);
}
static PyObject* snapshot_vertex_count(SbpySnapshot* self, void* closure) {
    (void)closure;
    return PyLong_FromUnsignedLong(self->data->vertex_count);
}
static PyObject* snapshot_energies(SbpySnapshot* self, void* closure) {
    (void)closure;
    const sb_energies* e = &self->data->energies;
    return Py_BuildValue("{s:d,s:d,s:d,s:d}", "kinetic", e->kinetic, "gravity", e->gravity, "internal",
                         sb_energies_internal(e), "total", sb_energies_total(e));
}

static PyGetSetDef snapshot_getset[] = {
    {"positions", (getter)snapshot_positions, NULL,
     "Positions, m: a read-only (n, 3) view in softbond.REAL_DTYPE, valid until release.", NULL},
    {"velocities", (getter)snapshot_velocities, NULL, "Velocities, m/s: a read-only (n, 3) view.", NULL},
    {"sequence", (getter)snapshot_sequence, NULL, "1 for the first snapshot published, then 2, 3, ...", NULL},
    {"step", (getter)snapshot_step, NULL, "The solver's step count when published.", NULL},
    {"time", (getter)snapshot_time, NULL, "Simulated time, s.", NULL},
    {"vertex_count", (getter)snapshot_vertex_count, NULL, "Vertices it holds.", NULL},
    {"energies", (getter)snapshot_energies, NULL, "kinetic, gravity, internal, total (J).", NULL},
    {NULL}};

static PyMethodDef snapshot_methods[] = {
    {"release", (PyCFunction)snapshot_release, METH_NOARGS,
     "release() -> None\n\nLets go of the snapshot (the writer may reuse it); its views must not be read after."},
    {"__enter__", (PyCFunction)snapshot_enter, METH_NOARGS, NULL},
    {"__exit__", (PyCFunction)snapshot_exit, METH_VARARGS, NULL},
    {NULL}};

PyTypeObject SbpySnapshotType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "softbond.Snapshot",
    .tp_basicsize = sizeof(SbpySnapshot),
    .tp_dealloc = (destructor)snapshot_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "One published state, held (StateBuffer.acquire()); use it in a with-block.",
    .tp_methods = snapshot_methods,
    .tp_getset = snapshot_getset,
};
