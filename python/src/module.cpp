// The fuzzycsg Python module (`fuzzycsg._fuzzycsg`; the package `fuzzycsg` wraps it): trees,
// evaluation and gradients, the engines, and the batched evaluation under the PyTorch layer.
// The library's errors become Python exceptions with the same one-line message the program
// prints: InputError (a ValueError) for bad input, OptionError (an InputError) for an option out
// of range, naming the option as the keyword argument spells it.

#include <pybind11/pybind11.h>

#include <exception>
#include <new>

#include "common.hpp"
#include "fuzzycsg/core/error.hpp"
#include "fuzzycsg/eval/evaluator.hpp"

namespace py = pybind11;

PYBIND11_MODULE(_fuzzycsg, m) {
  m.doc() = "fuzzycsg: fuzzy CSG trees, their evaluation and gradients, and the engines";
  static py::exception<fuzzycsg::InputError> input_error(m, "InputError", PyExc_ValueError);
  static py::exception<fuzzycsg::OptionError> option_error(m, "OptionError", input_error.ptr());
  static py::exception<fuzzycsg::Error> error(m, "Error", PyExc_RuntimeError);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const fuzzycsg::OptionError& e) {
      option_error(e.what());
    } catch (const fuzzycsg::InputError& e) {
      input_error(e.what());
    } catch (const fuzzycsg::Error& e) {
      error(e.what());
    }
  });
  fuzzycsg::python::register_tree(m);
  fuzzycsg::python::register_engines(m);
  fuzzycsg::python::register_layer(m);
}
