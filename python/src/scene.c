/* softbond.Scene: a YAML scene loaded by the scene loader (libsoftbond_scene),
 * as `softbond run` loads it: the defaults, the file, the overrides, the
 * checks. Overrides are "key=value" strings or a dict (its values written
 * as YAML flow scalars, sequences and maps by softbond._dicts); a scene
 * from a dict is written to a temporary file and loaded the same way. */
#include "sbpy.h"

/** A list of "key=value" strings from a dict or a sequence of str (new reference). */
static PyObject* override_list(PyObject* overrides) {
    if (!overrides || overrides == Py_None) return PyList_New(0);
    if (PyDict_Check(overrides)) {
        PyObject* helpers = PyImport_ImportModule("softbond._dicts");
        if (!helpers) return NULL;
        PyObject* list = PyObject_CallMethod(helpers, "overrides", "O", overrides);
        Py_DECREF(helpers);
        return list;
    }
    PyObject* list = PySequence_List(overrides);
    if (!list) {
        PyErr_SetString(PyExc_TypeError, "Scene.load(): 'overrides' must be a dict or a list of 'key=value' strings");
        return NULL;
    }
    return list;
}

static PyObject* scene_load(PyObject* cls, PyObject* args, PyObject* kwargs) {
    static char* keywords[] = {"path", "overrides", NULL};
    PyObject *path, *overrides = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O&|O:load", keywords, PyUnicode_FSConverter, &path, &overrides))
        return NULL;
    PyObject* list = override_list(overrides);
    Py_ssize_t n = list ? PyList_GET_SIZE(list) : 0;
    const char** texts = list ? PyMem_Calloc((size_t)n + 1, sizeof *texts) : NULL;
    for (Py_ssize_t i = 0; texts && i < n; i++) {
        PyObject* item = PyList_GET_ITEM(list, i);
        texts[i] = PyUnicode_Check(item) ? PyUnicode_AsUTF8(item) : NULL;
        if (!texts[i]) {
            PyErr_Format(PyExc_TypeError, "Scene.load(): overrides[%zd] must be a 'key=value' str", i);
            PyMem_Free(texts);
            texts = NULL;
        }
    }
    if (!texts) {
        if (list && !PyErr_Occurred()) PyErr_NoMemory();
        Py_XDECREF(list);
        Py_DECREF(path);
        return NULL;
    }
    sb_scene_file* scene = NULL;
    sb_error err = {{0}};
    sb_status status;
    Py_BEGIN_ALLOW_THREADS status = sb_scene_file_load(PyBytes_AS_STRING(path), texts, (size_t)n, &scene, &err);
    Py_END_ALLOW_THREADS PyMem_Free(texts);
    Py_DECREF(list);
    Py_DECREF(path);
    if (status != SB_OK) return sbpy_raise(status, err.message);
    SbpyScene* self = (SbpyScene*)((PyTypeObject*)cls)->tp_alloc((PyTypeObject*)cls, 0);
    if (!self) {
        sb_scene_file_destroy(scene);
        return NULL;
    }
    self->scene = scene;
    return (PyObject*)self;
}

static PyObject* scene_from_dict(PyObject* cls, PyObject* args, PyObject* kwargs) {
    static char* keywords[] = {"scene", "base_dir", "overrides", NULL};
    PyObject *dict, *base_dir = Py_None, *overrides = Py_None;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O!|OO:from_dict", keywords, &PyDict_Type, &dict, &base_dir,
                                     &overrides))
        return NULL;
    PyObject* helpers = PyImport_ImportModule("softbond._dicts");
    if (!helpers) return NULL;
    PyObject* scene = PyObject_CallMethod(helpers, "load_dict", "OOOO", cls, dict, base_dir, overrides);
    Py_DECREF(helpers);
    return scene;
}

static void scene_dealloc(SbpyScene* self) {
    sb_scene_file_destroy(self->scene);
    Py_TYPE(self)->tp_free((PyObject*)self);
}

static PyObject* scene_number(SbpyScene* self, PyObject* arg) {
    const char* key = PyUnicode_Check(arg) ? PyUnicode_AsUTF8(arg) : NULL;
    if (!key) return PyErr_Format(PyExc_TypeError, "number(): 'key' must be a str");
    double value;
    sb_error err = {{0}};
    sb_status status = sb_scene_file_number(self->scene, key, &value, &err);
    if (status != SB_OK) return sbpy_raise(status, err.message);
    return PyFloat_FromDouble(value);
}

static PyObject* scene_model(SbpyScene* self, void* closure) {
    (void)closure;
    /* A view of the scene's model that keeps the scene (its owner) alive. */
    return sbpy_model_wrap((sb_model*)sb_scene_file_model(self->scene), (PyObject*)self);
}
static PyObject* scene_dt(SbpyScene* self, void* closure) {
    (void)closure;
    return PyFloat_FromDouble(sb_scene_file_dt(self->scene));
}
static PyObject* scene_duration(SbpyScene* self, void* closure) {
    (void)closure;
    return PyFloat_FromDouble(sb_scene_file_duration(self->scene));
}
static PyObject* scene_frame_interval(SbpyScene* self, void* closure) {
    (void)closure;
    return PyFloat_FromDouble(sb_scene_file_frame_interval(self->scene));
}
static PyObject* scene_name(SbpyScene* self, void* closure) {
    (void)closure;
    return PyUnicode_FromString(sb_scene_file_name(self->scene));
}
static PyObject* scene_integrator(SbpyScene* self, void* closure) {
    (void)closure;
    return PyUnicode_FromString(sb_integrator_name(sb_scene_file_solver_def(self->scene)->integrator));
}
static PyObject* scene_gravity(SbpyScene* self, void* closure) {
    (void)closure;
    const double* g = sb_scene_file_solver_def(self->scene)->gravity;
    return Py_BuildValue("(ddd)", g[0], g[1], g[2]);
}

static PyObject* scene_colliders(SbpyScene* self, void* closure) {
    (void)closure;
    return sbpy_scene_colliders(self);
}
static PyObject* scene_handles(SbpyScene* self, void* closure) {
    (void)closure;
    return sbpy_scene_handles(self);
}

static PyGetSetDef scene_getset[] = {
    {"colliders", (getter)scene_colliders, NULL,
     "The scene's colliders (a tuple of Collider, owned by the scene: set_pose drives them).", NULL},
    {"handles", (getter)scene_handles, NULL, "The scene's handles (a tuple of Handle, owned by the scene).", NULL},
    {"model", (getter)scene_model, NULL, "The scene's Model (the mesh placed, pinned and fixed).", NULL},
    {"dt", (getter)scene_dt, NULL, "The time step, s.", NULL},
    {"duration", (getter)scene_duration, NULL, "The simulated time the scene runs for, s.", NULL},
    {"frame_interval", (getter)scene_frame_interval, NULL, "Simulated time between frames, s.", NULL},
    {"name", (getter)scene_name, NULL, "The file's name without directory and extension.", NULL},
    {"integrator", (getter)scene_integrator, NULL, "The scene's integrator's name.", NULL},
    {"gravity", (getter)scene_gravity, NULL, "The scene's gravity, m/s^2.", NULL},
    {NULL}};

static PyMethodDef scene_methods[] = {
    {"load", (PyCFunction)(void (*)(void))scene_load, METH_VARARGS | METH_KEYWORDS | METH_CLASS,
     "load(path, overrides=None) -> Scene\n\nLoads a YAML scene as `softbond run` does. overrides: a dict of\n"
     "dotted keys ({'bond.k': 200, 'mesh.nx': 21, 'gravity': [0, 0, 0]}) or 'key=value' strings, later ones\n"
     "winning. Errors name the file and line: FileError, ParseError (unknown key, wrong type), InvalidError."},
    {"from_dict", (PyCFunction)(void (*)(void))scene_from_dict, METH_VARARGS | METH_KEYWORDS | METH_CLASS,
     "from_dict(scene, base_dir=None, overrides=None) -> Scene\n\nA scene from a dict with the YAML file's\n"
     "structure ({'mesh': {'generator': 'sheet', 'nx': 5}, 'bond': {'k': 50}, ...}); relative paths in it are\n"
     "relative to base_dir (default: the current directory)."},
    {"number", (PyCFunction)scene_number, METH_O,
     "number(key) -> float\n\nAny number or integer setting by its dotted key ('mesh.nx', 'stop.kinetic_energy')."},
    {NULL}};

PyTypeObject SbpySceneType = {
    PyVarObject_HEAD_INIT(NULL, 0).tp_name = "softbond.Scene",
    .tp_basicsize = sizeof(SbpyScene),
    .tp_dealloc = (destructor)scene_dealloc,
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A loaded YAML scene: its Model, its solver definition and the run's settings. Make one with\n"
              "Scene.load(path, overrides) or Scene.from_dict(d); run it with Solver(scene) and advance(scene.dt).\n"
              "Its haptics and output settings are not acted on.",
    .tp_methods = scene_methods,
    .tp_getset = scene_getset,
};
