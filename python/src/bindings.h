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

// Arguments of any Python value that the binding reads with numpy.asarray (or as a
// number): plain objects, named in the signatures pybind11 writes (help(), the .pyi
// stubs) by what they take.
inline bool any_object(PyObject*) { return true; }
class ArrayLike : public pyb::object { // numpy.typing.ArrayLike
 public:
  PYBIND11_OBJECT_DEFAULT(ArrayLike, object, any_object)
};
class OptionalArrayLike : public pyb::object { // Optional[numpy.typing.ArrayLike]
 public:
  PYBIND11_OBJECT_DEFAULT(OptionalArrayLike, object, any_object)
};
class HitsAndStats : public pyb::tuple { // Tuple[numpy.ndarray, numpy.ndarray]
 public:
  PYBIND11_OBJECT_DEFAULT(HitsAndStats, tuple, any_object)
};
class OptionalArray : public pyb::object { // Optional[numpy.ndarray]
 public:
  PYBIND11_OBJECT_DEFAULT(OptionalArray, object, any_object)
};

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

// Context.trace's `stats` as its two overloads take it (False: hits; True: hits and
// counters), so that type checkers see which it returns. Either takes what bool() makes
// False or True respectively.
struct StatsOff {};
struct StatsOn {};

} // namespace masq::py

namespace pybind11::detail {
// Loads when bool(src) is `Value`; the name is what signatures show.
template <class T, bool Value>
struct flag_caster {
  PYBIND11_TYPE_CASTER(T, const_name("typing.Literal[") + const_name<Value>("True", "False") + const_name("]"));
  bool load(handle src, bool) {
    const int truth = PyObject_IsTrue(src.ptr());
    if (truth < 0) {
      PyErr_Clear();
      return false;
    }
    return (truth == 1) == Value;
  }
  static handle cast(T, return_value_policy, handle) { return pybind11::bool_(Value).release(); }
};
template <>
struct type_caster<masq::py::StatsOff> : flag_caster<masq::py::StatsOff, false> {};
template <>
struct type_caster<masq::py::StatsOn> : flag_caster<masq::py::StatsOn, true> {};
template <>
struct handle_type_name<masq::py::ArrayLike> {
  static constexpr auto name = const_name("numpy.typing.ArrayLike");
};
template <>
struct handle_type_name<masq::py::OptionalArrayLike> {
  static constexpr auto name = const_name("Optional[numpy.typing.ArrayLike]");
};
template <>
struct handle_type_name<masq::py::HitsAndStats> {
  static constexpr auto name = const_name("Tuple[numpy.ndarray, numpy.ndarray]");
};
template <>
struct handle_type_name<masq::py::OptionalArray> {
  static constexpr auto name = const_name("Optional[numpy.ndarray]");
};
} // namespace pybind11::detail
