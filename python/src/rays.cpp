#include "rays.h"
#include "arrays.h"
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <sstream>

namespace masq::py {

namespace {

using Shape = std::vector<pyb::ssize_t>;

// Packed rays reuse one buffer per thread: a fresh one would cost its page faults on
// every trace (a million rays: 32 MB).
std::vector<api::Ray>& packed_buffer() {
  thread_local std::vector<api::Ray> rays;
  return rays;
}

pyb::module_ numpy() { return pyb::module_::import("numpy"); }

// How the rays were given: what a bad value's message calls its argument.
enum class RayForm {
  Arrays,  // origins and directions
  Six,     // one (..., 6) array: origin in columns 0-2, direction in 3-5
  Records, // a ray_dtype array
};

std::size_t element_count(const Shape& shape) {
  std::size_t n = 1;
  for (pyb::ssize_t s : shape) n *= static_cast<std::size_t>(s);
  return n;
}

Shape shape_of(const pyb::array& a, int drop_last) {
  return Shape(a.shape(), a.shape() + (a.ndim() - drop_last));
}

pyb::tuple shape_tuple(const Shape& shape, int columns) {
  pyb::list l;
  for (pyb::ssize_t s : shape) l.append(s);
  if (columns) l.append(columns);
  return pyb::tuple(l);
}

// numpy's broadcasting of two shapes (aligned at the right; sizes equal, or one of them
// 1), or nothing when they do not broadcast.
std::optional<Shape> broadcast(const Shape& a, const Shape& b) {
  Shape out(std::max(a.size(), b.size()));
  for (std::size_t i = 0; i < out.size(); ++i) {
    const pyb::ssize_t x = i < a.size() ? a[a.size() - 1 - i] : 1;
    const pyb::ssize_t y = i < b.size() ? b[b.size() - 1 - i] : 1;
    if (x != y && x != 1 && y != 1) return std::nullopt;
    out[out.size() - 1 - i] = x == 1 ? y : x;
  }
  return out;
}

// One input of the pack loop: value k of ray i at data[i * stride + k]. A stride of 0
// repeats one row for every ray (a number, a broadcast row); masq's own rays['org'] and
// hits['normal'] are read in place with their records' strides.
struct Column {
  const float* data = nullptr;
  std::ptrdiff_t stride = 0;
  pyb::object keep; // owns data
  bool number = false; // a Python number: messages give no row
};

// Whether a float32 array of one row per ray (no broadcast to do) can be read in place:
// 1-D rows of values, or (n, columns) rows whose columns lie side by side, at any row
// stride; C-contiguous arrays of more axes too. Else nothing: numpy is asked.
std::optional<Column> as_it_lies(const pyb::array& a, const Shape& shape, int columns) {
  constexpr auto f4 = static_cast<pyb::ssize_t>(sizeof(float));
  if (!a.dtype().equal(pyb::dtype::of<float>()) || shape_of(a, columns ? 1 : 0) != shape) return std::nullopt;
  if (reinterpret_cast<std::uintptr_t>(a.data()) % alignof(float) != 0) return std::nullopt;
  Column c;
  c.data = static_cast<const float*>(a.data());
  c.keep = a;
  const pyb::ssize_t flat_axes = columns ? 2 : 1;
  if (a.ndim() == flat_axes && a.strides(0) % f4 == 0 && (!columns || a.strides(1) == f4)) {
    c.stride = a.strides(0) / f4;
    return c;
  }
  if (a.flags() & pyb::array::c_style) {
    c.stride = columns ? columns : 1;
    return c;
  }
  return std::nullopt;
}

// `a` broadcast to `shape` (+ (columns,) when columns > 0) and flattened to one row per
// ray: read in place when it is float32 with its columns side by side (as_it_lies, or
// numpy's broadcast view flattened without a copy); else one copy
// (numpy.ascontiguousarray), converting the dtype.
Column column(const pyb::array& a, const Shape& shape, int columns, ArgName name) {
  require_float(a, name);
  if (std::optional<Column> c = as_it_lies(a, shape, columns)) return *c; // the common case: no numpy call
  pyb::module_ np = numpy();
  pyb::object b = np.attr("broadcast_to")(a, shape_tuple(shape, columns));
  pyb::array flat = columns ? b.attr("reshape")(-1, columns) : b.attr("reshape")(-1);
  if (std::optional<Column> c = as_it_lies(flat, {static_cast<pyb::ssize_t>(element_count(shape))}, columns))
    return *c;
  flat = np.attr("ascontiguousarray")(flat, "float32");
  Column c;
  c.data = static_cast<const float*>(flat.data());
  c.stride = columns ? columns : 1;
  c.keep = flat;
  return c;
}

// tmin and tmax are numbers (Python's, numpy's, a 0-d array), None (their defaults) or
// arrays broadcast against the rays. Whether `value` is taken as a number:
bool is_number(const pyb::handle& value) {
  if (pyb::isinstance<pyb::list>(value) || pyb::isinstance<pyb::tuple>(value)) return false;
  return !pyb::isinstance<pyb::array>(value) || pyb::reinterpret_borrow<pyb::array>(value).ndim() == 0;
}

double number(const pyb::handle& value, ArgName name) {
  try {
    return pyb::float_(pyb::reinterpret_borrow<pyb::object>(value)).cast<double>();
  } catch (pyb::error_already_set&) {
    throw pyb::type_error(name.text() + ": expected a number or an array of numbers, got " +
                          pyb::str(pyb::type::of(value)).cast<std::string>());
  }
}

// The shape a bound adds to the rays' broadcast: () for a number or None, which leave
// `array` null (a default pyb::object); an array's own shape, the array in `array`.
Shape bound_shape(const pyb::handle& value, ArgName name, pyb::object& array) {
  if (value.is_none() || is_number(value)) return {};
  pyb::array a = as_array(value, name);
  array = a;
  return shape_of(a, 0);
}

// The bound's column: the array broadcast, or the number (`fallback` for None) read
// from `storage`, which must outlive the pack (no numpy array is made for it).
Column bound_column(const pyb::handle& value, const pyb::object& array, const Shape& shape, float fallback,
                    ArgName name, float& storage) {
  if (array) return column(pyb::reinterpret_borrow<pyb::array>(array), shape, 0, name);
  storage = value.is_none() ? fallback : static_cast<float>(number(value, name));
  Column c;
  c.data = &storage;
  c.number = true;
  return c;
}

// tmax as the kernels take it: +inf (Python's "no bound") as the largest float.
float largest_bound(float tmax) {
  return tmax == std::numeric_limits<float>::infinity() ? std::numeric_limits<float>::max() : tmax;
}

// The first bad value of the rays: NaN anywhere, or an infinite value but in tmax
// (column 7 of a ray's 8 floats: org, tmin, dir, tmax).
struct BadValue {
  std::size_t ray;
  int column;
  bool nan;
};

// Whether any value of the rays is NaN or infinite: one branch-free pass, the common
// case; find_bad's slow scan runs only when this finds something (an infinite tmax, or a
// value to name).
bool any_nonfinite(std::span<const api::Ray> rays) {
  static_assert(sizeof(api::Ray) == 8 * sizeof(float));
  return py::any_nonfinite(reinterpret_cast<const float*>(rays.data()), 8 * rays.size());
}

std::optional<BadValue> find_bad(std::span<const api::Ray> rays) {
  if (!any_nonfinite(rays)) return std::nullopt;
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const api::Ray& r = rays[i];
    const float v[8] = {r.org.x, r.org.y, r.org.z, r.tmin, r.dir.x, r.dir.y, r.dir.z, r.tmax};
    for (int k = 0; k < 8; ++k)
      if (std::isnan(v[k]) || (k != 7 && std::isinf(v[k]))) return BadValue{i, k, std::isnan(v[k])};
  }
  return std::nullopt;
}

// "row 4" (1-D rays), "ray [2, 5]" (more dimensions), "" (one ray of shape ()).
std::string ray_place(const Shape& shape, std::size_t ray, const char* one_d) {
  if (shape.empty()) return "";
  if (shape.size() == 1) return std::string(one_d) + " " + std::to_string(ray);
  Shape index(shape.size());
  for (std::size_t k = shape.size(); k-- > 0;) {
    index[k] = static_cast<pyb::ssize_t>(ray % static_cast<std::size_t>(shape[k]));
    ray /= static_cast<std::size_t>(shape[k]);
  }
  std::string s = "ray [";
  for (std::size_t k = 0; k < index.size(); ++k) {
    if (k) s += ", "; // appended apart: GCC 12 warns (a false positive) of ", " + std::string
    s += std::to_string(index[k]);
  }
  return s + "]";
}

// ValueError naming the argument that held the bad value and where it lies in it.
[[noreturn]] void bad_ray(const char* function, RayForm form, const Shape& shape, const BadValue& b,
                          const Column* tmin = nullptr, const Column* tmax = nullptr) {
  static const char* const parts[] = {"origin", "origin", "origin", "tmin", "direction", "direction", "direction",
                                      "tmax"};
  const std::string what = b.nan ? "NaN" : "infinite value";
  const std::string rule = " (coordinates and ray bounds must be finite numbers; tmax may be +inf)";
  std::ostringstream s;
  s << function << ": ";
  if (form == RayForm::Records) {
    const std::string place = ray_place(shape, b.ray, "ray");
    s << "rays: " << (place.empty() ? "the ray" : place) << " has " << (b.nan ? "a NaN" : "an infinite") << " "
      << parts[b.column] << rule;
    throw pyb::value_error(s.str());
  }
  const bool bound = b.column == 3 || b.column == 7;
  const Column* given = b.column == 3 ? tmin : tmax;
  if (bound) {
    s << parts[b.column] << ": " << what;
    const std::string place = ray_place(shape, b.ray, "row");
    if (!(given && given->number) && !place.empty()) s << " in " << place;
    throw pyb::value_error(s.str() + rule);
  }
  // Coordinates: the column within the argument that holds them.
  const bool origin = b.column < 3;
  const int col = origin ? b.column : b.column - 4;
  if (form == RayForm::Six) s << "rays: " << what << " (" << parts[b.column] << ")";
  else s << (origin ? "origins" : "directions") << ": " << what;
  const std::string place = ray_place(shape, b.ray, "row");
  s << (place.empty() ? "" : " in " + place) << " (column " << (form == RayForm::Six && !origin ? col + 3 : col)
    << ")";
  throw pyb::value_error(s.str() + rule);
}

// A view of the per-thread buffer as a ray_dtype array of `shape`, for numpy to copy
// into; the buffer outlives it (it is only used while the rays are packed).
pyb::array buffer_view(std::vector<api::Ray>& buffer, const Shape& shape) {
  pyb::capsule no_owner(buffer.data(), [](void*) {});
  return pyb::array(ray_dtype(), shape, buffer.data(), no_owner);
}

RayInput records(const pyb::array& a, const pyb::handle& tmin, const pyb::handle& tmax, const char* function) {
  for (const auto& [value, name] : {std::pair{tmin, "tmin"}, std::pair{tmax, "tmax"}})
    if (!value.is_none())
      throw pyb::value_error(std::string(function) + ": " + name +
                             ": not used with a ray_dtype array (its tmin and tmax fields hold the bounds)");
  RayInput in;
  in.shape = shape_of(a, 0);
  const std::size_t n = element_count(in.shape);
  const bool in_place = (a.flags() & pyb::array::c_style) &&
                        reinterpret_cast<std::uintptr_t>(a.data()) % alignof(api::Ray) == 0;
  if (in_place) {
    in.rays = {static_cast<const api::Ray*>(a.data()), n};
    bool infinite_tmax = false;
    if (any_nonfinite(in.rays)) {
      if (const std::optional<BadValue> bad = find_bad(in.rays)) bad_ray(function, RayForm::Records, in.shape, *bad);
      for (const api::Ray& r : in.rays) infinite_tmax |= r.tmax == std::numeric_limits<float>::infinity();
    }
    if (!infinite_tmax) {
      in.given = a;
      return in;
    }
  }
  // Strided (rays[::2], a transposed grid) or holding +inf bounds: one copy into the
  // buffer, by numpy for a strided array (it walks any layout).
  std::vector<api::Ray>& packed = packed_buffer();
  packed.resize(n);
  if (in_place) std::copy(in.rays.begin(), in.rays.end(), packed.begin());
  else if (n) numpy().attr("copyto")(buffer_view(packed, in.shape), a);
  for (api::Ray& r : packed) r.tmax = largest_bound(r.tmax);
  in.rays = packed;
  if (!in_place)
    if (const std::optional<BadValue> bad = find_bad(in.rays)) bad_ray(function, RayForm::Records, in.shape, *bad);
  return in;
}

// ValueError unless `a` has `columns` values in its last axis.
void require_last_axis(const pyb::array& a, ArgName name, int columns, const char* hint = "") {
  if (a.ndim() < 1 || a.shape(a.ndim() - 1) != columns)
    throw pyb::value_error(name.text() + ": expected shape (..., " + std::to_string(columns) + "), got " +
                           shape_text(a) + hint);
}

// One argument's part in the rays' shape: its shape (directions: without the last axis).
struct ShapePart {
  Shape shape;
  ArgName name;
  const char* what; // "leading shape" or "shape"
};

// The rays' shape: origins' leading shape broadcast with each part in turn (numpy's
// rules); ValueError naming the first part that does not fit.
Shape ray_shape(const Shape& origins, std::initializer_list<ShapePart> parts) {
  Shape shape = origins;
  bool first = true;
  for (const ShapePart& p : parts) {
    std::optional<Shape> b = broadcast(shape, p.shape);
    if (!b)
      throw pyb::value_error(p.name.text() + ": " + p.what + " " + shape_text(p.shape) +
                             " does not broadcast against " + (first ? "origins' leading shape " : "the rays' shape ") +
                             shape_text(shape) + " (numpy's rules: sizes equal or 1, aligned at the right)");
    shape = *b;
    first = false;
  }
  return shape;
}

} // namespace

RayInput ray_input(const pyb::handle& origins, const pyb::handle& directions, const pyb::handle& tmin,
                   const pyb::handle& tmax, const char* function) {
  const ArgName origins_name{function, "origins"}, directions_name{function, "directions"};
  pyb::array o = as_array(origins, origins_name);
  if (o.dtype().equal(ray_dtype())) {
    if (!directions.is_none())
      throw pyb::value_error(std::string(function) + ": directions: not used with a ray_dtype array (it holds them)");
    return records(o, tmin, tmax, function);
  }
  RayForm form = RayForm::Arrays;
  pyb::array d;
  if (directions.is_none()) {
    if (o.ndim() < 1 || o.shape(o.ndim() - 1) != 6)
      throw pyb::type_error(std::string(function) +
                            ": directions: missing (pass origins and directions as (..., 3) arrays, (..., 6) rays "
                            "holding origin and direction in each row, or one masq.ray_dtype array; origins has "
                            "shape " +
                            shape_text(o) + ")");
    require_float(o, {function, "rays"});
    form = RayForm::Six;
    d = o[pyb::make_tuple(pyb::ellipsis(), pyb::slice(3, 6, 1))];
    o = o[pyb::make_tuple(pyb::ellipsis(), pyb::slice(0, 3, 1))];
  } else {
    d = as_array(directions, directions_name);
    require_last_axis(o, origins_name, 3,
                      o.ndim() >= 1 && o.shape(o.ndim() - 1) == 6 ? " ((..., 6) rays hold their directions: pass no "
                                                                     "directions)"
                                                                   : "");
    require_last_axis(d, directions_name, 3);
  }
  const ArgName tmin_name{function, "tmin"}, tmax_name{function, "tmax"};
  pyb::object tmin_array, tmax_array;
  const Shape tmin_shape = bound_shape(tmin, tmin_name, tmin_array);
  const Shape tmax_shape = bound_shape(tmax, tmax_name, tmax_array);
  RayInput in;
  in.shape = ray_shape(shape_of(o, 1), {{shape_of(d, 1), directions_name, "leading shape"},
                                        {tmin_shape, tmin_name, "shape"},
                                        {tmax_shape, tmax_name, "shape"}});
  const ArgName rays_name{function, "rays"};
  const Column co = column(o, in.shape, 3, form == RayForm::Six ? rays_name : origins_name);
  const Column cd = column(d, in.shape, 3, form == RayForm::Six ? rays_name : directions_name);
  float tmin_number = 0, tmax_number = 0;
  const Column t0 = bound_column(tmin, tmin_array, in.shape, 0.0f, tmin_name, tmin_number);
  const Column t1 =
      bound_column(tmax, tmax_array, in.shape, std::numeric_limits<float>::infinity(), tmax_name, tmax_number);
  std::vector<api::Ray>& packed = packed_buffer();
  packed.resize(element_count(in.shape));
  for (std::size_t i = 0; i < packed.size(); ++i) {
    const auto at = [i](const Column& c) { return c.data + static_cast<std::ptrdiff_t>(i) * c.stride; };
    const float* po = at(co);
    const float* pd = at(cd);
    packed[i] = {{po[0], po[1], po[2]}, *at(t0), {pd[0], pd[1], pd[2]}, largest_bound(*at(t1))};
  }
  in.rays = packed;
  if (const std::optional<BadValue> bad = find_bad(in.rays)) bad_ray(function, form, in.shape, *bad, &t0, &t1);
  return in;
}

} // namespace masq::py
