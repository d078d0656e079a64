// The parts of the masq Python module (module.cpp assembles them). The bindings use
// the public C++ API only (include/masq/), as any other consumer of the library does.
#pragma once
#include "masq/types.h"
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <vector>

namespace masq::py {

namespace pyb = pybind11;

// The structured dtypes of rays, hits and counters: the public structs' own layouts, so
// arrays of them cross into the library without a copy (ray_dtype, hit_dtype and
// stats_dtype in the module). Made once by bind_records.
pyb::dtype ray_dtype();
pyb::dtype hit_dtype();
pyb::dtype stats_dtype();

// An uninitialised 1-D array of `n` records of `dtype`.
inline pyb::array record_array(const pyb::dtype& dtype, std::size_t n) {
  return pyb::array(dtype, std::vector<pyb::ssize_t>{static_cast<pyb::ssize_t>(n)});
}

// An array of ray_dtype holding `rays` (one copy).
pyb::array rays_to_numpy(const std::vector<api::Ray>& rays);

// masq.LoadWarning, the category of the loaders' repairs (a UserWarning subclass).
PyObject* load_warning();

void bind_records(pyb::module_& m);  // the dtypes
void bind_scene(pyb::module_& m);    // Scene
void bind_context(pyb::module_& m);  // AccelStats, Accel, Context

} // namespace masq::py
