/* Module functions for triangle mesh files: softbond.load_mesh reads one
 * (softbond's OBJ and OFF readers, assimp, a tetrahedral mesh's surface)
 * into NumPy arrays, softbond.export_mesh writes arrays out (PLY, OBJ,
 * glTF, IRIT, POV-Ray) through the library's exporter. */
#include "sbpy.h"

static PyObject* load_mesh(PyObject* module, PyObject* args) {
    (void)module;
    PyObject* path;
    if (!PyArg_ParseTuple(args, "O&:load_mesh", PyUnicode_FSConverter, &path)) return NULL;
    sb_mesh mesh = {0};
    sb_error err = {{0}};
    sb_status status;
    Py_BEGIN_ALLOW_THREADS status = sb_mesh_load(PyBytes_AS_STRING(path), &mesh, &err);
    Py_END_ALLOW_THREADS Py_DECREF(path);
    if (status != SB_OK) return sbpy_raise(status, err.message);
    npy_intp xdims[2] = {mesh.vertex_count, 3}, tdims[2] = {mesh.triangle_count, 3};
    PyObject* vertices = PyArray_SimpleNew(2, xdims, NPY_DOUBLE);
    PyObject* triangles = vertices ? PyArray_SimpleNew(2, tdims, NPY_UINT32) : NULL;
    PyObject* result = NULL;
    if (triangles) {
        memcpy(PyArray_DATA((PyArrayObject*)vertices), mesh.positions, (size_t)mesh.vertex_count * 3 * sizeof(double));
        memcpy(PyArray_DATA((PyArrayObject*)triangles), mesh.triangles,
               (size_t)mesh.triangle_count * 3 * sizeof(uint32_t));
        result = PyTuple_Pack(2, vertices, triangles);
    }
    Py_XDECREF(vertices);
    Py_XDECREF(triangles);
    sb_mesh_free(&mesh);
    return result;
}

static PyObject* export_mesh(PyObject* module, PyObject* args, PyObject* kwargs) {
    (void)module;
    static const char* function = "export_mesh()";
    static char* keywords[] = {"path", "vertices", "triangles", "format", "up", NULL};
    PyObject *path, *vertices, *triangles, *up = NULL;
    const char* format = NULL;
    if (!PyArg_ParseTupleAndKeywords(args, kwargs, "O&OO|$zO:export_mesh", keywords, PyUnicode_FSConverter, &path,
                                     &vertices, &triangles, &format, &up))
        return NULL;
    const char* text = PyBytes_AS_STRING(path);
    const char* dot = strrchr(text, '.');
    sb_mesh_export_def def = sb_default_mesh_export_def();
    if (!format) format = dot ? dot + 1 : "";
    if (strcmp(format, "itd") == 0) format = "irit";
    if (!sb_mesh_export_extension(format)) {
        Py_DECREF(path);
        return PyErr_Format(PyExc_ValueError, "%s: 'format' must be ply, obj, gltf, glb, irit or pov, not '%s'",
                            function, format);
    }
    if (up && sbpy_vec3(up, function, "up", def.up) < 0) {
        Py_DECREF(path);
        return NULL;
    }
    PyArrayObject* x = sbpy_array(vertices, function, "vertices", NPY_DOUBLE, 3);
    PyArrayObject* t = x ? sbpy_index_array(triangles, function, "triangles", 3) : NULL;
    uint32_t* corners = t ? PyMem_Malloc((size_t)PyArray_SIZE(t) * sizeof(uint32_t) + 1) : NULL;
    PyObject* result = NULL;
    if (corners) {
        const int64_t* tv = PyArray_DATA(t);
        for (npy_intp i = 0; i < PyArray_SIZE(t); i++) corners[i] = (uint32_t)tv[i];
        sb_mesh mesh = {(uint32_t)PyArray_DIM(x, 0), PyArray_DATA(x), (uint32_t)PyArray_DIM(t, 0), corners};
        sb_error err = {{0}};
        sb_status status = sb_mesh_export(text, format, &mesh, &def, &err);
        result = status == SB_OK ? Py_NewRef(Py_None) : sbpy_raise(status, err.message);
    } else if (t) {
        PyErr_NoMemory();
    }
    PyMem_Free(corners);
    Py_XDECREF(x);
    Py_XDECREF(t);
    Py_DECREF(path);
    return result;
}

PyMethodDef sbpy_mesh_functions[] = {
    {"load_mesh", (PyCFunction)load_mesh, METH_VARARGS,
     "load_mesh(path) -> (vertices, triangles)\n\nA triangle mesh file (OBJ and OFF by softbond's own readers, which\n"
     "keep the vertex order; anything assimp reads; a tetrahedral mesh's surface) as a (n, 3) float64 and a\n"
     "(t, 3) uint32 array. FileError or ParseError name the file and line."},
    {"export_mesh", (PyCFunction)(void (*)(void))export_mesh, METH_VARARGS | METH_KEYWORDS,
     "export_mesh(path, vertices, triangles, *, format=None, up=(0, 0, 1)) -> None\n\nWrites a triangle mesh:\n"
     "format 'ply', 'obj', 'gltf', 'glb', 'irit' or 'pov' (default: the path's extension); up: which way is up\n"
     "in a POV-Ray scene. A solver's state: export_mesh(path, solver.positions, solver.triangles)."},
    {NULL}};
