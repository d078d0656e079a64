// The masq Python module (_masq, imported by the masq package): exceptions, option
// names, and the parts bound in bind_*.cpp and records.cpp.
#include "bindings.h"
#include "masq/masq.h"
#include <pybind11/stl.h>

namespace masq::py {

PyObject* load_warning() {
  static PyObject* type = PyErr_NewExceptionWithDoc(
      "masq.LoadWarning", "A repair or assumption a scene file loader made (Scene.load).", PyExc_UserWarning, nullptr);
  return type;
}

namespace {

// {"method": {"ref": "what it does", ...}, ...}: every option table, for discovery.
template <class Table>
pyb::dict option_rows(const Table& table) {
  pyb::dict d;
  for (const auto& row : table.rows()) d[row.name] = row.help;
  return d;
}

} // namespace

} // namespace masq::py

PYBIND11_MODULE(_masq, m) {
  namespace pyb = pybind11;
  using namespace masq;
  m.doc() = "masq: ray tracing of long, thin primitives (capsules, round cones, spheres, cubic curves) and "
            "triangles on cpu, Vulkan, OpenCL and the driver's ray tracing (docs/python.md).";
  // masq.Error: bad input and device failures, with masq's one-line message.
  // masq.BackendUnavailable (a masq.Error): a backend that cannot run here.
  static pyb::exception<Error> error(m, "Error", PyExc_RuntimeError);
  static pyb::exception<BackendUnavailable> unavailable(m, "BackendUnavailable", error.ptr());
  pyb::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const BackendUnavailable& e) {
      PyErr_SetString(unavailable.ptr(), e.what());
    } catch (const Error& e) {
      PyErr_SetString(error.ptr(), e.what());
    }
  });
  // masq.LoadWarning (a UserWarning): a repair or assumption a file loader made.
  m.attr("LoadWarning") = pyb::handle(py::load_warning());
  m.attr("__version__") = api::version();
  pyb::dict options;
  options["method"] = py::option_rows(api::method_table);
  options["mode"] = py::option_rows(api::mode_table);
  options["builder"] = py::option_rows(api::builder_table);
  options["nodes"] = py::option_rows(api::node_format_table);
  options["curve_isect"] = py::option_rows(api::curve_isect_table);
  options["blas_occlusion"] = py::option_rows(api::blas_occlusion_table);
  m.attr("options") = options;
  m.def("backends", &api::Context::backends, "Every backend compiled in.");
  m.def("available_backends", &api::Context::available_backends, "The backends that open on this machine.");
  py::bind_records(m);
  py::bind_scene(m);
  py::bind_context(m);
}
