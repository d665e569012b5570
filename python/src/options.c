/* Arguments from Python: keyword tables, 3-vectors, NumPy arrays, keyframes.
 * Every failure names the function and the argument: TypeError for a value
 * of the wrong kind, ValueError for one of the right kind out of shape or
 * range. */
#include "sbpy.h"

static int option_value(const char* function, const sbpy_option* option, PyObject* value) {
    switch (option->kind) {
    case SBPY_DOUBLE: {
        double d = PyFloat_AsDouble(value);
        if (d == -1.0 && PyErr_Occurred()) {
            PyErr_Format(PyExc_TypeError, "%s: '%s' must be a number, not %s", function, option->name,
                         Py_TYPE(value)->tp_name);
            return -1;
        }
        *(double*)option->target = d;
        return 0;
    }
    case SBPY_INT: {
        if (!PyLong_Check(value) && !PyIndex_Check(value)) {
            PyErr_Format(PyExc_TypeError, "%s: '%s' must be an integer, not %s", function, option->name,
                         Py_TYPE(value)->tp_name);
            return -1;
        }
        long n = PyLong_AsLong(value);
        if (n == -1 && PyErr_Occurred()) return -1;
        if (n < INT32_MIN || n > INT32_MAX) {
            PyErr_Format(PyExc_ValueError, "%s: '%s' is out of range (%ld)", function, option->name, n);
            return -1;
        }
        *(int*)option->target = (int)n;
        return 0;
    }
    case SBPY_BOOL: {
        int truth = PyObject_IsTrue(value);
        if (truth < 0) return -1;
        *(bool*)option->target = truth;
        return 0;
    }
    case SBPY_VEC3: return sbpy_vec3(value, function, option->name, (double*)option->target);
    case SBPY_OBJECT: *(PyObject**)option->target = value; return 0;
    case SBPY_STRING:
        if (!PyUnicode_Check(value)) {
            PyErr_Format(PyExc_TypeError, "%s: '%s' must be a str, not %s", function, option->name,
                         Py_TYPE(value)->tp_name);
            return -1;
        }
        *(const char**)option->target = PyUnicode_AsUTF8(value);
        return *(const char**)option->target ? 0 : -1;
    }
    return 0;
}

int sbpy_options(const char* function, PyObject* kwargs, const sbpy_option* table, size_t count) {
    if (!kwargs) return 0;
    PyObject *key, *value;
    Py_ssize_t pos = 0;
    while (PyDict_Next(kwargs, &pos, &key, &value)) {
        const char* name = PyUnicode_AsUTF8(key);
        if (!name) return -1;
        size_t i = 0;
        while (i < count && strcmp(table[i].name, name) != 0) i++;
        if (i == count) {
            PyErr_Format(PyExc_TypeError, "%s got an unexpected keyword argument '%s'", function, name);
            return -1;
        }
        if (option_value(function, &table[i], value) < 0) return -1;
        if (table[i].given) *table[i].given = true;
    }
    return 0;
}

int sbpy_vec3(PyObject* value, const char* function, const char* name, double out[3]) {
    PyObject* seq = PySequence_Fast(value, "");
    if (!seq || PySequence_Fast_GET_SIZE(seq) != 3) {
        Py_XDECREF(seq);
        PyErr_Format(PyExc_TypeError, "%s: '%s' must be a sequence of 3 numbers", function, name);
        return -1;
    }
    for (int k = 0; k < 3; k++) {
        out[k] = PyFloat_AsDouble(PySequence_Fast_GET_ITEM(seq, k));
        if (out[k] == -1.0 && PyErr_Occurred()) {
            Py_DECREF(seq);
            PyErr_Format(PyExc_TypeError, "%s: '%s' must be a sequence of 3 numbers", function, name);
            return -1;
        }
    }
    Py_DECREF(seq);
    return 0;
}

static void shape_text(PyArrayObject* array, char* text, size_t size) {
    size_t used = (size_t)PyOS_snprintf(text, size, "(");
    for (int d = 0; d < PyArray_NDIM(array) && used < size; d++)
        used += (size_t)PyOS_snprintf(text + used, size - used, d ? ", %zd" : "%zd", (Py_ssize_t)PyArray_DIM(array, d));
    if (used < size) PyOS_snprintf(text + used, size - used, PyArray_NDIM(array) == 1 ? ",)" : ")");
}

PyArrayObject* sbpy_array(PyObject* obj, const char* function, const char* name, int type, npy_intp columns) {
    PyArrayObject* array = (PyArrayObject*)PyArray_FROMANY(obj, type, 0, 0, NPY_ARRAY_IN_ARRAY | NPY_ARRAY_FORCECAST);
    if (!array) {
        PyErr_Clear();
        PyErr_Format(PyExc_TypeError, "%s: '%s' must be an array of numbers, not %s", function, name,
                     Py_TYPE(obj)->tp_name);
        return NULL;
    }
    bool good = columns ? PyArray_NDIM(array) == 2 && PyArray_DIM(array, 1) == columns : PyArray_NDIM(array) == 1;
    if (!good) {
        char shape[64];
        shape_text(array, shape, sizeof shape);
        if (columns)
            PyErr_Format(PyExc_ValueError, "%s: '%s' must have shape (n, %zd), got %s", function, name,
                         (Py_ssize_t)columns, shape);
        else
            PyErr_Format(PyExc_ValueError, "%s: '%s' must have shape (n,), got %s", function, name, shape);
        Py_DECREF(array);
        return NULL;
    }
    return array;
}

PyArrayObject* sbpy_index_array(PyObject* obj, const char* function, const char* name, npy_intp columns) {
    PyArrayObject* probe = (PyArrayObject*)PyArray_FROMANY(obj, NPY_NOTYPE, 0, 0, 0);
    if (probe) {
        bool integral = PyArray_ISINTEGER(probe) || PyArray_SIZE(probe) == 0;
        Py_DECREF(probe);
        if (!integral) {
            PyErr_Format(PyExc_TypeError, "%s: '%s' must hold integers (vertex indices)", function, name);
            return NULL;
        }
    } else {
        PyErr_Clear();
    }
    PyArrayObject* array = sbpy_array(obj, function, name, NPY_INT64, columns);
    if (!array) return NULL;
    const int64_t* v = PyArray_DATA(array);
    for (npy_intp i = 0; i < PyArray_SIZE(array); i++) {
        if (v[i] < 0 || v[i] > (int64_t)UINT32_MAX - 1) {
            PyErr_Format(PyExc_ValueError, "%s: '%s' holds %lld, not a vertex index", function, name, (long long)v[i]);
            Py_DECREF(array);
            return NULL;
        }
    }
    return array;
}

int sbpy_per_element(PyObject* obj, const char* function, const char* name, npy_intp count, double fallback,
                     PyArrayObject** owner, const double** values, double* scalar) {
    *owner = NULL;
    *scalar = fallback;
    *values = NULL;
    bool scalar_given = obj && (PyFloat_Check(obj) || PyLong_Check(obj) || PyArray_CheckScalar(obj));
    if (obj && obj != Py_None && !scalar_given) {
        *owner = sbpy_array(obj, function, name, NPY_DOUBLE, 0);
        if (!*owner) return -1;
        if (PyArray_DIM(*owner, 0) != count) {
            PyErr_Format(PyExc_ValueError, "%s: '%s' must be a number or %zd numbers, got %zd", function, name,
                         (Py_ssize_t)count, (Py_ssize_t)PyArray_DIM(*owner, 0));
            Py_CLEAR(*owner);
            return -1;
        }
        *values = PyArray_DATA(*owner);
        return 0;
    }
    if (scalar_given) {
        *scalar = PyFloat_AsDouble(obj);
        if (*scalar == -1.0 && PyErr_Occurred()) {
            PyErr_Format(PyExc_TypeError, "%s: '%s' must be a number or an array of numbers", function, name);
            return -1;
        }
    }
    return 0;
}

int sbpy_keyframes(PyObject* obj, const char* function, sb_keyframe** out, uint32_t* count) {
    *out = NULL;
    *count = 0;
    if (!obj || obj == Py_None) return 0;
    PyObject* seq = PySequence_Fast(obj, "");
    if (!seq) {
        PyErr_Format(PyExc_TypeError, "%s: 'path' must be a sequence of (time, translate, rotate)", function);
        return -1;
    }
    Py_ssize_t n = PySequence_Fast_GET_SIZE(seq);
    sb_keyframe* frames = PyMem_Calloc(n ? (size_t)n : 1, sizeof *frames);
    if (!frames) {
        Py_DECREF(seq);
        PyErr_NoMemory();
        return -1;
    }
    for (Py_ssize_t i = 0; i < n; i++) {
        PyObject* item = PySequence_Fast_GET_ITEM(seq, i);
        double time = -1;
        PyObject *translate = NULL, *rotate = NULL;
        PyObject* tuple = PySequence_Check(item) ? PySequence_Tuple(item) : NULL;
        if (!tuple || !PyArg_ParseTuple(tuple, "dO|O", &time, &translate, &rotate) ||
            sbpy_vec3(translate, function, "path[].translate", frames[i].translate) < 0 ||
            (rotate && sbpy_vec3(rotate, function, "path[].rotate", frames[i].rotate) < 0)) {
            Py_XDECREF(tuple);
            Py_DECREF(seq);
            PyMem_Free(frames);
            PyErr_Format(PyExc_TypeError, "%s: path[%zd] must be (time, (x, y, z)[, (rx, ry, rz)])", function, i);
            return -1;
        }
        Py_DECREF(tuple);
        frames[i].time = time;
    }
    Py_DECREF(seq);
    *out = frames;
    *count = (uint32_t)n;
    return 0;
}

int sbpy_interpolation(const char* name, const char* function, sb_interpolation* out) {
    if (!name || strcmp(name, "linear") == 0)
        *out = SB_INTERPOLATION_LINEAR;
    else if (strcmp(name, "smooth") == 0)
        *out = SB_INTERPOLATION_SMOOTH;
    else {
        PyErr_Format(PyExc_ValueError, "%s: 'interpolation' must be 'linear' or 'smooth', not '%s'", function, name);
        return -1;
    }
    return 0;
}

PyObject* sbpy_vector3(const double v[3]) {
    npy_intp three = 3;
    PyObject* array = PyArray_SimpleNew(1, &three, NPY_DOUBLE);
    if (array) memcpy(PyArray_DATA((PyArrayObject*)array), v, 3 * sizeof(double));
    return array;
}
