#include "arrays.h"
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

namespace masq::py {

namespace {

std::string shape_text(const pyb::array& a) {
  std::ostringstream s;
  s << "(";
  for (pyb::ssize_t i = 0; i < a.ndim(); ++i) s << (i ? ", " : "") << a.shape(i);
  s << (a.ndim() == 1 ? ",)" : ")");
  return s.str();
}

std::string strides_text(const pyb::array& a) {
  std::ostringstream s;
  s << "(";
  for (pyb::ssize_t i = 0; i < a.ndim(); ++i) s << (i ? ", " : "") << a.strides(i);
  s << ")";
  return s.str();
}

std::string dtype_text(const pyb::array& a) { return pyb::str(a.dtype()).cast<std::string>(); }

// The argument as a numpy array: arrays as they are (a view, whatever its layout, so the
// layout checks below see what the caller passed), lists and tuples through
// numpy.asarray.
pyb::array as_array(const pyb::handle& value, ArgName name) {
  if (pyb::isinstance<pyb::array>(value)) return pyb::reinterpret_borrow<pyb::array>(value);
  if (value.is_none()) throw pyb::type_error(name.text() + ": expected an array, got None");
  try {
    return pyb::module_::import("numpy").attr("asarray")(value);
  } catch (pyb::error_already_set& e) {
    throw pyb::type_error(name.text() + ": cannot be read as an array (" + std::string(e.what()) + ")");
  }
}

void require_contiguous(const pyb::array& a, ArgName name) {
  if (!(a.flags() & pyb::array::c_style))
    throw pyb::value_error(name.text() + ": the array is not C-contiguous (shape " + shape_text(a) + ", strides " +
                           strides_text(a) + " bytes); pass numpy.ascontiguousarray(" + name.argument + ")");
}

void require_shape(const pyb::array& a, ArgName name, const std::vector<std::size_t>& tail, long rows,
                   const std::string& expected) {
  bool ok = static_cast<std::size_t>(a.ndim()) == tail.size() + 1;
  for (std::size_t i = 0; ok && i < tail.size(); ++i) ok = static_cast<std::size_t>(a.shape(i + 1)) == tail[i];
  if (!ok) throw pyb::value_error(name.text() + ": expected shape " + expected + ", got " + shape_text(a));
  if (rows >= 0 && a.shape(0) != rows)
    throw pyb::value_error(name.text() + ": " + std::to_string(a.shape(0)) + " rows where " + std::to_string(rows) +
                           " are needed (one per ray or primitive), shape " + shape_text(a));
}

// float32 as it lies, or a float32 copy of float16/float64; other dtypes raise.
pyb::array_t<float> as_float32(const pyb::array& a, ArgName name) {
  const char kind = a.dtype().kind();
  if (kind != 'f')
    throw pyb::type_error(name.text() + ": expected a float32 or float64 array, got dtype " + dtype_text(a));
  if (a.dtype().itemsize() == 4 && a.dtype().equal(pyb::dtype::of<float>()))
    return pyb::reinterpret_borrow<pyb::array_t<float>>(a);
  return a.attr("astype")("float32");
}

void require_finite(const pyb::array_t<float>& a, ArgName name, std::size_t per_row, bool allow_inf) {
  const float* p = a.data();
  const std::size_t n = static_cast<std::size_t>(a.size());
  if (!any_nonfinite(p, n)) return;
  for (std::size_t i = 0; i < n; ++i)
    if (std::isnan(p[i]) || (!allow_inf && std::isinf(p[i]))) {
      std::ostringstream s;
      s << name.text() << ": " << (std::isnan(p[i]) ? "NaN" : "infinite value");
      if (per_row > 1) s << " in row " << i / per_row << " (column " << i % per_row << ")";
      else s << " in row " << i;
      throw pyb::value_error(s.str() + " (coordinates, radii and ray bounds must be finite numbers)");
    }
}

std::string rows_of(std::size_t columns) { return columns ? "(n, " + std::to_string(columns) + ")" : "(n,)"; }

} // namespace

bool any_nonfinite(const float* p, std::size_t n) {
  // NaN and infinity are the floats whose exponent bits are all ones.
  constexpr std::uint32_t kExponent = 0x7f800000u;
  std::uint32_t found = 0;
  for (std::size_t i = 0; i < n; ++i) {
    std::uint32_t bits;
    std::memcpy(&bits, p + i, sizeof bits);
    found |= static_cast<std::uint32_t>((bits & kExponent) == kExponent);
  }
  return found != 0;
}

pyb::array_t<float> float_rows(const pyb::handle& value, ArgName name, std::size_t columns, long rows,
                               bool allow_inf) {
  pyb::array a = as_array(value, name);
  std::vector<std::size_t> tail;
  if (columns) tail.push_back(columns);
  require_shape(a, name, tail, rows, rows_of(columns));
  require_contiguous(a, name);
  pyb::array_t<float> f = as_float32(a, name);
  require_finite(f, name, columns ? columns : 1, allow_inf);
  return f;
}

pyb::array_t<float> float_blocks(const pyb::handle& value, ArgName name, std::size_t a_size, std::size_t b_size) {
  pyb::array a = as_array(value, name);
  require_shape(a, name, {a_size, b_size}, -1,
                "(n, " + std::to_string(a_size) + ", " + std::to_string(b_size) + ")");
  require_contiguous(a, name);
  pyb::array_t<float> f = as_float32(a, name);
  require_finite(f, name, a_size * b_size, false);
  return f;
}

PerRowFloat per_row_float(const pyb::handle& value, ArgName name, std::size_t rows, bool allow_inf) {
  PerRowFloat out;
  const bool sequence = pyb::isinstance<pyb::list>(value) || pyb::isinstance<pyb::tuple>(value);
  const bool zero_d = pyb::isinstance<pyb::array>(value) && pyb::reinterpret_borrow<pyb::array>(value).ndim() == 0;
  if (!sequence && (zero_d || !pyb::isinstance<pyb::array>(value))) {
    // A number: Python's, numpy's scalars, a 0-d array (anything float() takes).
    double d = 0;
    try {
      d = pyb::float_(pyb::reinterpret_borrow<pyb::object>(value)).cast<double>();
    } catch (pyb::error_already_set&) {
      throw pyb::type_error(name.text() + ": expected a number or an array of " + std::to_string(rows) +
                            " numbers, got " + pyb::str(pyb::type::of(value)).cast<std::string>());
    }
    if (std::isnan(d) || (!allow_inf && std::isinf(d)))
      throw pyb::value_error(name.text() + ": " + (std::isnan(d) ? "NaN" : "infinite value") +
                             " (coordinates, radii and ray bounds must be finite numbers)");
    out.scalar_ = static_cast<float>(d);
    return out;
  }
  out.array_ = float_rows(value, name, 0, static_cast<long>(rows), allow_inf);
  out.values_ = out.array_.data();
  return out;
}

std::vector<std::uint32_t> index_rows(const pyb::handle& value, ArgName name, std::size_t columns) {
  pyb::array a = as_array(value, name);
  require_shape(a, name, {columns}, -1, rows_of(columns));
  require_contiguous(a, name);
  const char kind = a.dtype().kind();
  if (kind != 'i' && kind != 'u')
    throw pyb::type_error(name.text() + ": expected an integer array (e.g. uint32), got dtype " + dtype_text(a));
  // int64 holds every uint32 and every negative value, so one conversion checks both ends.
  auto wide = pyb::array_t<std::int64_t, pyb::array::c_style | pyb::array::forcecast>::ensure(a);
  std::vector<std::uint32_t> out(static_cast<std::size_t>(wide.size()));
  const std::int64_t* p = wide.data();
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (p[i] < 0 || p[i] > std::numeric_limits<std::uint32_t>::max())
      throw pyb::value_error(name.text() + ": index " + std::to_string(p[i]) + " in row " +
                             std::to_string(i / columns) + " is outside [0, 2^32)");
    out[i] = static_cast<std::uint32_t>(p[i]);
  }
  return out;
}

} // namespace masq::py
