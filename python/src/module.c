/* softbond._core: the module, its exception classes and constants.
 *
 * softbond.Error is the base of one class per library status
 * (InvalidError, FileError, ParseError, DegenerateError, UnstableError,
 * BusyError; SB_ERR_NOMEM raises MemoryError); each carries the library's
 * one line as its message and the status's name in .status. InvalidError
 * is also a ValueError and FileError an OSError, so that generic handlers
 * catch them too. */
#define SBPY_MODULE_FILE
#include "sbpy.h"

static PyObject* error_base;
static PyObject* error_classes[SB_ERR_BUSY + 1];

PyObject* sbpy_error_class(sb_status status) {
    if (status == SB_ERR_NOMEM) return PyExc_MemoryError;
    if ((unsigned)status > SB_ERR_BUSY || !error_classes[status]) return error_base;
    return error_classes[status];
}

PyObject* sbpy_raise(sb_status status, const char* message) {
    PyObject* cls = sbpy_error_class(status);
    PyObject* value = PyObject_CallFunction(cls, "s", message && message[0] ? message : sb_status_name(status));
    if (!value) return NULL;
    if (cls != PyExc_MemoryError) {
        PyObject* name = PyUnicode_FromString(sb_status_name(status));
        if (!name || PyObject_SetAttrString(value, "status", name) < 0) {
            Py_XDECREF(name);
            Py_DECREF(value);
            return NULL;
        }
        Py_DECREF(name);
    }
    PyErr_SetObject(cls, value);
    Py_DECREF(value);
    return NULL;
}

void sbpy_pending_keep(sbpy_pending* pending) {
    if (pending->type) {
        PyErr_Clear();
        return;
    }
    PyErr_Fetch(&pending->type, &pending->value, &pending->traceback);
}

int sbpy_pending_raise(sbpy_pending* pending) {
    if (!pending->type) return 0;
    PyErr_Restore(pending->type, pending->value, pending->traceback);
    pending->type = pending->value = pending->traceback = NULL;
    return -1;
}

/** Creates softbond.<name>(bases) with a docstring and adds it to the module. */
static PyObject* add_error(PyObject* module, const char* name, PyObject* bases, const char* doc) {
    char qualified[64];
    PyOS_snprintf(qualified, sizeof qualified, "softbond.%s", name);
    PyObject* cls = PyErr_NewExceptionWithDoc(qualified, doc, bases, NULL);
    if (!cls) return NULL;
    if (PyModule_AddObjectRef(module, name, cls) < 0) {
        Py_DECREF(cls);
        return NULL;
    }
    return cls;
}

static int add_errors(PyObject* module) {
    error_base = add_error(module, "Error", NULL,
                           "A softbond library call failed. str(error) is the library's one line (it names the "
                           "file, line or element); error.status the status's short name.");
    if (!error_base) return -1;
    static const struct {
        sb_status status;
        const char* name;
        PyObject** extra;
        const char* doc;
    } table[] = {
        {SB_ERR_INVALID, "InvalidError", &PyExc_ValueError, "Bad argument or bad model data (SB_ERR_INVALID)."},
        {SB_ERR_IO, "FileError", &PyExc_OSError, "A file could not be read or written (SB_ERR_IO)."},
        {SB_ERR_PARSE, "ParseError", NULL, "Malformed file contents: YAML, a mesh, a scene key (SB_ERR_PARSE)."},
        {SB_ERR_DEGENERATE, "DegenerateError", NULL, "A collapsed edge or triangle met during a step."},
        {SB_ERR_UNSTABLE, "UnstableError", NULL, "The state became non-finite or ran away (SB_ERR_UNSTABLE)."},
        {SB_ERR_BUSY, "BusyError", NULL, "A state buffer had no free slot: nothing was written (SB_ERR_BUSY)."},
    };
    for (size_t i = 0; i < sizeof table / sizeof table[0]; i++) {
        PyObject* bases = table[i].extra ? PyTuple_Pack(2, error_base, *table[i].extra) : PyTuple_Pack(1, error_base);
        if (!bases) return -1;
        error_classes[table[i].status] = add_error(module, table[i].name, bases, table[i].doc);
        Py_DECREF(bases);
        if (!error_classes[table[i].status]) return -1;
    }
    return 0;
}

static int add_types(PyObject* module) {
    PyTypeObject* types[] = {&SbpyModelType,       &SbpySolverType,   &SbpyColliderType, &SbpyHandleType,
                             &SbpyStateBufferType, &SbpySnapshotType, &SbpySceneType};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++) {
        if (PyType_Ready(types[i]) < 0) return -1;
        const char* dot = strrchr(types[i]->tp_name, '.');
        if (PyModule_AddObjectRef(module, dot ? dot + 1 : types[i]->tp_name, (PyObject*)types[i]) < 0) return -1;
    }
    return 0;
}

static int add_constants(PyObject* module) {
    PyObject* integrators = PyTuple_New(SB_INTEGRATOR_COUNT);
    if (!integrators) return -1;
    for (int i = 0; i < SB_INTEGRATOR_COUNT; i++)
        PyTuple_SET_ITEM(integrators, i, PyUnicode_FromString(sb_integrator_name((sb_integrator)i)));
    if (PyModule_AddObject(module, "INTEGRATORS", integrators) < 0) {
        Py_DECREF(integrators);
        return -1;
    }
    PyObject* terms = PyTuple_New(SB_TERM_COUNT);
    if (!terms) return -1;
    for (int i = 0; i < SB_TERM_COUNT; i++) PyTuple_SET_ITEM(terms, i, PyUnicode_FromString(sb_term_name((sb_term)i)));
    if (PyModule_AddObject(module, "TERMS", terms) < 0) {
        Py_DECREF(terms);
        return -1;
    }
    PyObject* real = (PyObject*)PyArray_DescrFromType(SBPY_NPY_REAL);
    if (!real || PyModule_AddObject(module, "REAL_DTYPE", real) < 0) {
        Py_XDECREF(real);
        return -1;
    }
    return PyModule_AddIntConstant(module, "DOUBLE", SB_DOUBLE);
}

static struct PyModuleDef module_def = {
    PyModuleDef_HEAD_INIT,
    .m_name = "softbond._core",
    .m_doc = "The C extension under the softbond package (import softbond, not this).",
    .m_size = -1,
    .m_methods = sbpy_mesh_functions,
};

PyMODINIT_FUNC PyInit__core(void) {
    import_array();
    PyObject* module = PyModule_Create(&module_def);
    if (!module) return NULL;
    if (add_errors(module) < 0 || add_types(module) < 0 || add_constants(module) < 0) {
        Py_DECREF(module);
        return NULL;
    }
    return module;
}
