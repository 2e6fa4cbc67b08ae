#pragma once
// Shared by the Python module's source files: NumPy arrays in and out, checked, and the parts of
// the module each file registers.

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <cmath>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "fuzzycsg/core/tree.hpp"

namespace fuzzycsg::python {

namespace py = pybind11;

// A C-contiguous array of T: the caller's own memory when it already is one (no copy), a
// converted copy otherwise.
template <class T>
using CArray = py::array_t<T, py::array::c_style | py::array::forcecast>;

// `what` (an argument's name) must have `ndim` dimensions; a size of -1 takes any length.
// ValueError naming the argument and the shapes otherwise.
void check_shape(const py::array& a, const char* what, std::vector<py::ssize_t> shape);
// Every entry finite: ValueError naming the argument and the first bad entry otherwise.
template <class T>
void check_finite(const CArray<T>& a, const char* what) {
  const T* p = a.data();
  for (py::ssize_t i = 0; i < a.size(); ++i) {
    if (!std::isfinite(p[i])) {
      throw py::value_error(std::string(what) + ": entry " + std::to_string(i) + " is not finite");
    }
  }
}
// Arrays of any numeric dtype are accepted; anything else (strings, objects) is a TypeError.
template <class T>
CArray<T> as_array(const py::handle& h, const char* what) {
  const py::array a = py::array::ensure(h);
  if (!a || !(a.dtype().kind() == 'f' || a.dtype().kind() == 'i' || a.dtype().kind() == 'u' ||
              a.dtype().kind() == 'b')) {
    throw py::type_error(std::string(what) + ": a numeric array expected");
  }
  return CArray<T>::ensure(a);
}

// N x dim points for a tree of dimension `dim`, float32, checked.
CArray<float> points_array(const py::handle& points, int dim);

// A NumPy array that owns a std::vector's memory (no copy).
template <class T>
py::array_t<T> to_numpy(std::vector<T>&& v, std::vector<py::ssize_t> shape) {
  auto* owner = new std::vector<T>(std::move(v));
  const py::capsule free_when_done(owner, [](void* p) { delete static_cast<std::vector<T>*>(p); });
  return py::array_t<T>(shape, owner->data(), free_when_done);
}

// Runs `work`, which must not touch Python objects, on a thread of its own while this thread
// waits with the GIL released and checks for signals every 50 ms: on Ctrl-C the engines are asked
// to stop (request_cancel), waited for, and KeyboardInterrupt is raised. An engine's call would
// otherwise hold the interpreter's main thread for as long as it runs.
void interruptible(const std::function<void()>& work);

// The parts of the module.
void register_tree(py::module_& m);
void register_engines(py::module_& m);
void register_layer(py::module_& m);

}  // namespace fuzzycsg::python
