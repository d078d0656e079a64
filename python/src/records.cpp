// The structured dtypes of the public Ray, Hit and RayStats: numpy describes each field
// at the struct's own offset and the struct's own size, so a buffer of one is a buffer
// of the other.
#include "bindings.h"
#include <cstddef>
#include <cstring>

namespace masq::py {

namespace {

struct Field {
  const char* name;
  const char* format; // numpy's: "<f4", "(3,)<f4", "<i4"
  std::size_t offset;
};

pyb::dtype make_dtype(std::initializer_list<Field> fields, std::size_t itemsize) {
  pyb::list names, formats, offsets;
  for (const Field& f : fields) {
    names.append(f.name);
    formats.append(f.format);
    offsets.append(f.offset);
  }
  pyb::dict spec;
  spec["names"] = names;
  spec["formats"] = formats;
  spec["offsets"] = offsets;
  spec["itemsize"] = itemsize;
  return pyb::dtype::from_args(spec);
}

// Kept alive for the interpreter's life (the module holds them too).
pyb::dtype* g_ray = nullptr;
pyb::dtype* g_hit = nullptr;
pyb::dtype* g_stats = nullptr;

} // namespace

pyb::dtype ray_dtype() { return *g_ray; }
pyb::dtype hit_dtype() { return *g_hit; }
pyb::dtype stats_dtype() { return *g_stats; }

pyb::array rays_to_numpy(const std::vector<api::Ray>& rays) {
  pyb::array out = record_array(ray_dtype(), rays.size());
  if (!rays.empty()) std::memcpy(out.mutable_data(), static_cast<const void*>(rays.data()), rays.size() * sizeof(api::Ray));
  return out;
}

void bind_records(pyb::module_& m) {
  using api::Hit;
  using api::Ray;
  using api::RayStats;
  g_ray = new pyb::dtype(make_dtype({{"org", "(3,)<f4", offsetof(Ray, org)},
                                     {"tmin", "<f4", offsetof(Ray, tmin)},
                                     {"dir", "(3,)<f4", offsetof(Ray, dir)},
                                     {"tmax", "<f4", offsetof(Ray, tmax)}},
                                    sizeof(Ray)));
  g_hit = new pyb::dtype(make_dtype({{"t", "<f4", offsetof(Hit, t)},
                                     {"prim", "<i4", offsetof(Hit, prim)},
                                     {"geom", "<i4", offsetof(Hit, geometry)},
                                     {"inst", "<i4", offsetof(Hit, instance)},
                                     {"normal", "(3,)<f4", offsetof(Hit, normal)},
                                     {"u", "<f4", offsetof(Hit, u)},
                                     {"v", "<f4", offsetof(Hit, v)}},
                                    sizeof(Hit)));
  g_stats = new pyb::dtype(make_dtype({{"tlas_nodes", "<i4", offsetof(RayStats, tlas_nodes)},
                                       {"blas_nodes", "<i4", offsetof(RayStats, blas_nodes)},
                                       {"transforms", "<i4", offsetof(RayStats, transforms)},
                                       {"isect_calls", "<i4", offsetof(RayStats, isect_calls)}},
                                      sizeof(RayStats)));
  m.attr("ray_dtype") = *g_ray;
  m.attr("hit_dtype") = *g_hit;
  m.attr("stats_dtype") = *g_stats;
}

} // namespace masq::py
