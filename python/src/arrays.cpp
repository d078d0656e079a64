#include "arrays.h"
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

namespace masq::py {

namespace {

std::string dtype_text(const pyb::array& a) { return pyb::str(a.dtype()).cast<std::string>(); }

void require_shape(const pyb::array& a, ArgName name, const std::vector<std::size_t>& tail, long rows,
                   const std::string& expected) {
  bool ok = static_cast<std::size_t>(a.ndim()) == tail.size() + 1;
  for (std::size_t i = 0; ok && i < tail.size(); ++i) ok = static_cast<std::size_t>(a.shape(i + 1)) == tail[i];
  if (!ok) throw pyb::value_error(name.text() + ": expected shape " + expected + ", got " + shape_text(a));
  if (rows >= 0 && a.shape(0) != rows)
    throw pyb::value_error(name.text() + ": " + std::to_string(a.shape(0)) + " rows where " + std::to_string(rows) +
                           " are needed (one per ray or primitive), shape " + shape_text(a));
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

std::string shape_text(const std::vector<pyb::ssize_t>& shape) {
  std::ostringstream s;
  s << "(";
  for (std::size_t i = 0; i < shape.size(); ++i) s << (i ? ", " : "") << shape[i];
  s << (shape.size() == 1 ? ",)" : ")");
  return s.str();
}

std::string shape_text(const pyb::array& a) {
  return shape_text(std::vector<pyb::ssize_t>(a.shape(), a.shape() + a.ndim()));
}

pyb::array as_array(const pyb::handle& value, ArgName name) {
  if (pyb::isinstance<pyb::array>(value)) return pyb::reinterpret_borrow<pyb::array>(value);
  if (value.is_none()) throw pyb::type_error(name.text() + ": expected an array, got None");
  try {
    return pyb::module_::import("numpy").attr("asarray")(value);
  } catch (pyb::error_already_set& e) {
    throw pyb::type_error(name.text() + ": cannot be read as an array (" + std::string(e.what()) + ")");
  }
}

void require_float(const pyb::array& a, ArgName name) {
  if (a.dtype().kind() != 'f')
    throw pyb::type_error(name.text() + ": expected a float32 or float64 array, got dtype " + dtype_text(a));
}

// The array as C-contiguous float32: in place when it is one, else one copy that converts
// the dtype and gathers strided or broadcast rows together (numpy.ascontiguousarray).
pyb::array_t<float> contiguous_float32(const pyb::array& a, ArgName name) {
  require_float(a, name);
  if (a.dtype().equal(pyb::dtype::of<float>()) && (a.flags() & pyb::array::c_style))
    return pyb::reinterpret_borrow<pyb::array_t<float>>(a);
  return pyb::module_::import("numpy").attr("ascontiguousarray")(a, "float32");
}

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
  pyb::array_t<float> f = contiguous_float32(a, name);
  require_finite(f, name, columns ? columns : 1, allow_inf);
  return f;
}

pyb::array_t<float> float_blocks(const pyb::handle& value, ArgName name, std::size_t a_size, std::size_t b_size) {
  pyb::array a = as_array(value, name);
  require_shape(a, name, {a_size, b_size}, -1,
                "(n, " + std::to_string(a_size) + ", " + std::to_string(b_size) + ")");
  pyb::array_t<float> f = contiguous_float32(a, name);
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

namespace masq::py {

std::array<double, 3> vec3_arg(const pyb::handle& value, ArgName name) {
  pyb::array a = as_array(value, name);
  if (a.dtype().kind() != 'f' && a.dtype().kind() != 'i' && a.dtype().kind() != 'u')
    throw pyb::type_error(name.text() + ": expected three numbers, got dtype " + dtype_text(a));
  if (a.ndim() != 1 || a.shape(0) != 3)
    throw pyb::value_error(name.text() + ": expected three numbers (shape (3,)), got shape " + shape_text(a));
  auto d = pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>::ensure(a);
  std::array<double, 3> v{d.data()[0], d.data()[1], d.data()[2]};
  for (int k = 0; k < 3; ++k)
    if (!std::isfinite(v[std::size_t(k)]))
      throw pyb::value_error(name.text() + ": component " + std::to_string(k) + " is not finite");
  return v;
}

} // namespace masq::py
