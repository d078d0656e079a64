// Checks and views of the numpy arrays the bindings take. Every check names the argument
// ("Scene.add_capsules: a: ..."), so a notebook user sees which array was wrong: the
// dtype (TypeError), the shape, a non-finite value (ValueError). Arrays are taken as
// numpy hands them over: strided, transposed and broadcast arrays are copied (once), not
// refused.
#pragma once
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <cstddef>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace masq::py {

namespace pyb = pybind11;

// What an argument is called in messages: "Context.trace: origins".
struct ArgName {
  const char* function;
  const char* argument;
  std::string text() const { return std::string(function) + ": " + argument; }
};

// A float array of `columns` columns per row (columns 0: a 1-D array), as C-contiguous
// float32. A C-contiguous float32 array is used where it lies (no copy); float64 and
// other layouts are converted (one copy); any other dtype or a wrong shape raises naming
// `name`.
// `rows` < 0 takes any row count; otherwise the row count must equal it. Values must be
// finite unless `allow_inf` (NaN never is).
pyb::array_t<float> float_rows(const pyb::handle& value, ArgName name, std::size_t columns, long rows = -1,
                               bool allow_inf = false);

// Like float_rows for arrays of shape (rows, a, b), e.g. curves' (n, 4, 3) control points.
pyb::array_t<float> float_blocks(const pyb::handle& value, ArgName name, std::size_t a, std::size_t b);

// A per-row float: a Python number (the same for every row) or a 1-D array of `rows`
// values (checked as float_rows), read in place.
class PerRowFloat {
 public:
  float operator[](std::size_t row) const { return values_ ? values_[row] : scalar_; }

 private:
  friend PerRowFloat per_row_float(const pyb::handle&, ArgName, std::size_t, bool);
  pyb::array_t<float> array_; // keeps values_ alive
  const float* values_ = nullptr;
  float scalar_ = 0;
};
PerRowFloat per_row_float(const pyb::handle& value, ArgName name, std::size_t rows, bool allow_inf = false);

// An integer array of `columns` columns per row (any signed or unsigned integer dtype,
// any layout), every value in [0, 2^32); returned as uint32.
std::vector<std::uint32_t> index_rows(const pyb::handle& value, ArgName name, std::size_t columns);

// Whether any of `n` floats is NaN or infinite: a branch-free pass the compiler
// vectorises (a million rays check in about a millisecond), for the common case where
// nothing is; callers then look for the first one to name it.
bool any_nonfinite(const float* p, std::size_t n);

// The argument as a numpy array: arrays as they are (a view, whatever its layout), lists,
// tuples and numbers through numpy.asarray; None and what numpy cannot read raise
// TypeError naming `name`.
pyb::array as_array(const pyb::handle& value, ArgName name);

// TypeError naming `name` unless `a` holds floats (float16, float32, float64).
void require_float(const pyb::array& a, ArgName name);

// The array (any float dtype, else TypeError) as C-contiguous float32: in place when it
// is one, else one copy that converts the dtype and gathers strided or broadcast values
// together (numpy.ascontiguousarray).
pyb::array_t<float> contiguous_float32(const pyb::array& a, ArgName name);

// "(4, 3)", "(4,)", "()": a shape as numpy prints it.
std::string shape_text(const pyb::array& a);
std::string shape_text(const std::vector<pyb::ssize_t>& shape);

// A point or direction given as three numbers (a sequence or an array of shape (3,)),
// finite, in double precision.
std::array<double, 3> vec3_arg(const pyb::handle& value, ArgName name);

// The rows of a checked array.
inline std::size_t row_count(const pyb::array& a) { return a.ndim() == 0 ? 0 : static_cast<std::size_t>(a.shape(0)); }

} // namespace masq::py
