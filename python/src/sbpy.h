/* The softbond Python extension (softbond._core): what its files share.
 *
 * Design: every Python object owns one library object (a model, a solver, a
 * collider, a handle, a state buffer, a scene) and holds references to the
 * Python objects whose library objects it points at, so that Python's
 * reference counting keeps the library's lifetimes (a model outlives its
 * solvers, colliders and handles outlive the solver they are attached to).
 * Library errors become softbond.Error subclasses carrying the library's
 * one-line message; bad arguments become TypeError or ValueError naming the
 * argument. Keyword options are read through one table-driven parser
 * (sbpy_options), so every constructor reports an unknown or mistyped
 * keyword the same way. */
#ifndef SBPY_H
#define SBPY_H

#define PY_SSIZE_T_CLEAN
#include <Python.h>

#define PY_ARRAY_UNIQUE_SYMBOL sbpy_numpy_api
#ifndef SBPY_MODULE_FILE
#define NO_IMPORT_ARRAY
#endif
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include "softbond/softbond.h"
#include "softbond/collider.h"
#include "softbond/handle.h"
#include "softbond/blade.h"
#include "softbond/scene.h"
#include "softbond/state_buffer.h"

/** The NumPy type of sb_real: float32, or float64 in a SB_DOUBLE build. */
#if SB_DOUBLE
#define SBPY_NPY_REAL NPY_DOUBLE
#else
#define SBPY_NPY_REAL NPY_FLOAT
#endif

/* ---- errors (module.c) ---- */
/** Raises the softbond.Error subclass of status with message; returns NULL. */
PyObject* sbpy_raise(sb_status status, const char* message);
/** The exception class of a status (borrowed). */
PyObject* sbpy_error_class(sb_status status);

/* ---- keyword options (options.c) ---- */
typedef enum sbpy_option_kind {
    SBPY_DOUBLE, /**< double*: any real number */
    SBPY_INT,    /**< int*: an integer */
    SBPY_BOOL,   /**< bool*: any object's truth */
    SBPY_VEC3,   /**< double[3]: three numbers */
    SBPY_OBJECT, /**< PyObject** (borrowed), None kept as None */
    SBPY_STRING  /**< const char**: a str (valid while the kwargs live) */
} sbpy_option_kind;

/** One keyword a function accepts, and where its value goes. */
typedef struct sbpy_option {
    const char* name;
    sbpy_option_kind kind;
    void* target;
    bool* given; /**< set true when the keyword was passed; may be NULL */
} sbpy_option;

/** Reads kwargs (may be NULL) into the table's targets: TypeError for an
 * unknown keyword or a value of the wrong type, naming function and
 * keyword. Returns 0, or -1 with the exception set. */
int sbpy_options(const char* function, PyObject* kwargs, const sbpy_option* table, size_t count);
/** Three numbers from a sequence, TypeError/ValueError naming `name`. */
int sbpy_vec3(PyObject* value, const char* function, const char* name, double out[3]);
/** A C-contiguous array of `type` with `columns` columns (0: one dimension)
 * from obj; ValueError naming `name` for another shape. New reference or NULL. */
PyArrayObject* sbpy_array(PyObject* obj, const char* function, const char* name, int type, npy_intp columns);
/** An array of non-negative indices below 2^32 (int64 holding them): as
 * sbpy_array, ValueError for a negative or too large entry. */
PyArrayObject* sbpy_index_array(PyObject* obj, const char* function, const char* name, npy_intp columns);
/** Per-element values: a number for all of them, or `count` numbers.
 * *values points at count doubles (into *owner, an array to release). */
int sbpy_per_element(PyObject* obj, const char* function, const char* name, npy_intp count, double fallback,
                     PyArrayObject** owner, const double** values, double* scalar);
/** Keyframes from a sequence of (time, translate[3], rotate[3]) (rotate may
 * be left out): a PyMem array of *count keyframes, or NULL with
 * *count 0 for None. Returns 0 or -1. */
int sbpy_keyframes(PyObject* obj, const char* function, sb_keyframe** out, uint32_t* count);
/** "linear" or "smooth"; ValueError naming the argument. */
int sbpy_interpolation(const char* name, const char* function, sb_interpolation* out);
/** A new (3,) float64 array. */
PyObject* sbpy_vector3(const double v[3]);

/* ---- module functions (mesh.c) ---- */
extern PyMethodDef sbpy_mesh_functions[];

/* ---- types ---- */
extern PyTypeObject SbpyModelType;
extern PyTypeObject SbpySolverType;
extern PyTypeObject SbpyColliderType;
extern PyTypeObject SbpyHandleType;
extern PyTypeObject SbpyStateBufferType;
extern PyTypeObject SbpySnapshotType;
extern PyTypeObject SbpySceneType;

/** softbond.Model: a compiled model, immutable. */
typedef struct SbpyModel {
    PyObject_HEAD sb_model* model;
    PyObject* owner; /**< a Scene whose model this is, or NULL (then the model is owned) */
} SbpyModel;

/** The first exception a callback raised while the GIL was released for an
 * advance: kept (with the GIL held) and raised when the advance returns. */
typedef struct sbpy_pending {
    PyObject *type, *value, *traceback;
} sbpy_pending;
/** Keeps the current exception in pending unless one is kept already. */
void sbpy_pending_keep(sbpy_pending* pending);
/** Raises a kept exception: -1 when there was one, else 0. */
int sbpy_pending_raise(sbpy_pending* pending);

/** softbond.Collider. */
typedef struct SbpyCollider {
    PyObject_HEAD sb_collider* collider;
    PyObject* collide;    /**< a program's own collider: collide(...) -> contact or None */
    PyObject* begin_step; /**< its begin_step(t0, t1), or NULL */
    sbpy_pending pending; /**< an exception its callbacks raised */
    PyObject* owner;      /**< the Scene that owns the collider, or NULL (then it is owned) */
} SbpyCollider;

/** softbond.Handle. */
typedef struct SbpyHandle {
    PyObject_HEAD sb_handle* handle;
    PyObject* owner; /**< the Scene that owns the handle, or NULL (then it is owned) */
} SbpyHandle;

/** softbond.Scene. */
typedef struct SbpyScene {
    PyObject_HEAD sb_scene_file* scene;
} SbpyScene;

/** softbond.Solver. */
typedef struct SbpySolver {
    PyObject_HEAD sb_solver* solver;
    PyObject* model;          /**< the Model it advances */
    PyObject* scene;          /**< the Scene whose definition it was made with, or NULL */
    PyObject* colliders;      /**< tuple of Collider */
    PyObject* handles;        /**< tuple of Handle */
    PyObject* external_force; /**< callable or NULL */
    PyObject* on_break;       /**< callable or NULL */
    sb_collider** collider_ptrs;
    sb_handle** handle_ptrs;
    int busy;             /**< an advance is running with the GIL released */
    sbpy_pending pending; /**< an exception the external force or on_break raised */
} SbpySolver;

/** softbond.StateBuffer. */
typedef struct SbpyStateBuffer {
    PyObject_HEAD sb_state_buffer* buffer;
    uint32_t capacity;
} SbpyStateBuffer;

/** 0 when the solver is not advancing now; otherwise RuntimeError, -1. */
int sbpy_solver_ready(SbpySolver* self);

/** A scene's colliders or handles as a tuple of Collider or Handle objects that keep the scene alive. */
PyObject* sbpy_scene_colliders(SbpyScene* scene);
/** See sbpy_scene_colliders. */
PyObject* sbpy_scene_handles(SbpyScene* scene);

/** A Model object owning model (or a scene's, with owner). */
PyObject* sbpy_model_wrap(sb_model* model, PyObject* owner);

#endif
