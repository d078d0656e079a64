// Room for n more elements in a std::vector (any allocator), at least doubling its
// capacity when it grows: arrays that are appended to piece after piece (a scene's
// geometries packed one by one, BLAS after BLAS collapsed into one node array) then grow
// in linear time, where reserving exactly each time would copy the array at every piece.
#pragma once
#include <algorithm>
#include <cstddef>

namespace masq {

template <class Array> void reserve_more(Array& a, std::size_t n) {
  if (a.capacity() - a.size() < n) a.reserve(std::max(a.size() + n, 2 * a.capacity()));
}

} // namespace masq
