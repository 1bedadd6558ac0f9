// ForEachChunk: how the jobs of a parallel stage share a range of work: each claims chunks from a shared
// atomic cursor until none is left. Any thread; the cursor must be reset before the stage starts.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstdint>

namespace strata {

/// Calls `function(begin, end)` for chunks of [0, count) of `chunk` items that this job claims from `next`.
/// A stage run by `width` 1 job takes every chunk, in order, without claiming and leaves `next` alone: a
/// locked add per claim (two a stage) drains the store buffer, and a small world's step runs a dozen such
/// claims.
template <class Function>
void ForEachChunk(std::atomic<std::uint32_t>& next, std::uint32_t count, std::uint32_t chunk,
                  std::uint32_t width, Function&& function) {
  if (width == 1) {
    for (std::uint32_t begin = 0; begin < count; begin += chunk)
      function(begin, std::min(begin + chunk, count));
    return;
  }
  while (true) {
    const std::uint32_t begin = next.fetch_add(chunk, std::memory_order_relaxed);
    if (begin >= count) return;
    function(begin, std::min(begin + chunk, count));
  }
}

/// ForEachChunk item by item: `function(i)` for each i of the job's chunks.
template <class Function>
void ForEachChunkItem(std::atomic<std::uint32_t>& next, std::uint32_t count, std::uint32_t chunk,
                      std::uint32_t width, Function&& function) {
  ForEachChunk(next, count, chunk, width, [&](std::uint32_t begin, std::uint32_t end) {
    for (std::uint32_t i = begin; i < end; ++i) function(i);
  });
}

}  // namespace strata
