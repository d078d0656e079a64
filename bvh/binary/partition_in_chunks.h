// A partition of a long index range in chunks, possibly at once, with std::partition's
// own result (bvh/binary/binned_sah.cpp: the leaf order must not depend on the threads).
#pragma once
#include "bvh/binary/parallel.h"
#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

namespace masq {

// std::partition of order[first, first + count) by goes_left (indices, or references
// carrying what the predicate reads), the same result, its passes
// in chunks of `chunk` (>= 1) elements, possibly at once; returns the index of the first
// element that goes right.
// libstdc++'s partition (bidirectional) swaps the i-th element from the left that goes
// right with the i-th element from the right that goes left while the two have not
// crossed: exactly the elements that go right in [first, mid) in ascending order with
// those that go left in [mid, end) in descending order, pair by pair. Those pairs are
// found by counts per chunk and swapped.
template <class Array, class GoesLeft> // Array: a std::vector (any allocator)
int partition_in_chunks(Array& order, int first, int count, int chunk, GoesLeft goes_left) {
  if (count <= 0) return first;
  const int chunks = (count + chunk - 1) / chunk;
  // body(lo, hi, c) on chunk c = [lo, hi), possibly at once.
  auto for_chunks = [&](auto body) {
    parallel_chunks(std::size_t(chunks), 1, [&](std::size_t c0, std::size_t c1) {
      for (std::size_t c = c0; c < c1; ++c) {
        int lo = first + int(c) * chunk;
        body(lo, std::min(first + count, lo + chunk), int(c));
      }
    });
  };
  std::vector<char> left(static_cast<std::size_t>(count));
  std::vector<int> lefts(std::size_t(chunks), 0);
  for_chunks([&](int lo, int hi, int c) {
    for (int i = lo; i < hi; ++i) {
      left[std::size_t(i - first)] = goes_left(order[i]) ? 1 : 0;
      lefts[std::size_t(c)] += left[std::size_t(i - first)];
    }
  });
  int mid = first;
  for (int n : lefts) mid += n;
  // Per chunk: its misplaced elements (right-goers before mid, left-goers from mid on),
  // and where they start in the ascending and the descending list.
  std::vector<int> wrong_right(std::size_t(chunks), 0), wrong_left(std::size_t(chunks), 0);
  for_chunks([&](int lo, int hi, int c) {
    for (int i = lo; i < hi; ++i) {
      bool l = left[std::size_t(i - first)];
      if (i < mid && !l) ++wrong_right[std::size_t(c)];
      if (i >= mid && l) ++wrong_left[std::size_t(c)];
    }
  });
  std::vector<int> right_at(std::size_t(chunks), 0), left_at(std::size_t(chunks), 0);
  for (int c = 1; c < chunks; ++c) right_at[std::size_t(c)] = right_at[std::size_t(c - 1)] + wrong_right[std::size_t(c - 1)];
  for (int c = chunks - 2; c >= 0; --c) left_at[std::size_t(c)] = left_at[std::size_t(c + 1)] + wrong_left[std::size_t(c + 1)];
  const int pairs = right_at.back() + wrong_right.back();
  std::vector<int> to_right(static_cast<std::size_t>(pairs)), to_left(static_cast<std::size_t>(pairs));
  for_chunks([&](int lo, int hi, int c) {
    int r = right_at[std::size_t(c)], l = left_at[std::size_t(c)];
    for (int i = lo; i < hi; ++i)
      if (i < mid && !left[std::size_t(i - first)]) to_right[std::size_t(r++)] = i;
    for (int i = hi - 1; i >= lo; --i)
      if (i >= mid && left[std::size_t(i - first)]) to_left[std::size_t(l++)] = i;
  });
  parallel_chunks(std::size_t(pairs), 4096, [&](std::size_t a, std::size_t b) {
    for (std::size_t k = a; k < b; ++k) std::swap(order[std::size_t(to_right[k])], order[std::size_t(to_left[k])]);
  });
  return mid;
}

} // namespace masq
