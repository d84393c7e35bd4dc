// The Python module `iaa` (the compiled part, iaa._iaa; tools/python/package/__init__.py re-exports
// it): scenes, evaluation, rendering, enclosure, meshing and comparison as the `iaa` command runs
// them, with NumPy arrays for results. docs/python.md describes it.
#include <new>

#include "core/error.h"
#include "py_common.h"

PYBIND11_MODULE(_iaa, m) {
  namespace py = iaa::py;
  m.doc() =
      "iaa: guaranteed ray tracing, enclosure and meshing of implicit surfaces f(x,y,z) = 0 with "
      "interval arithmetic (the compiled part of the package iaa).";
  m.attr("__version__") = IAA_VERSION;
  // Bad input is a ValueError carrying the command's message; running out of memory a
  // MemoryError (pybind11's own translation).
  pybind11::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const iaa::Error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  py::bind_scene(m);
  py::bind_eval(m);
  py::bind_render(m);
  py::bind_enclose(m);
  py::bind_mesh(m);
}
