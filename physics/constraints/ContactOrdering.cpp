#include "physics/constraints/ContactOrdering.h"

#include <algorithm>

namespace strata {

void LinkContacts(BlockArena& arena, std::span<SolverContact* const> contacts, std::uint32_t*& begin,
                  std::uint32_t*& links) {
  const auto count = static_cast<std::uint32_t>(contacts.size());
  auto* by_body = arena.AllocateArray<std::uint64_t>(2 * count);
  std::uint32_t pairs = 0;
  for (std::uint32_t k = 0; k < count; ++k) {
    const ContactConstraint& c = *contacts[k]->constraint;
    if (c.dynamic_a) by_body[pairs++] = (std::uint64_t{c.body_a} << 32) | k;
    if (c.dynamic_b) by_body[pairs++] = (std::uint64_t{c.body_b} << 32) | k;
  }
  std::sort(by_body, by_body + pairs);
  // Where each contact's bodies' runs of contacts start and end in by_body.
  auto* run_begin = arena.AllocateArray<std::uint32_t>(2 * count);
  auto* run_end = arena.AllocateArray<std::uint32_t>(2 * count);
  auto* run_count = arena.AllocateArray<std::uint8_t>(count);
  std::fill(run_count, run_count + count, std::uint8_t{0});
  std::uint32_t capacity = count;  // itself
  for (std::uint32_t first = 0; first < pairs;) {
    std::uint32_t last = first + 1;
    while (last < pairs && (by_body[last] >> 32) == (by_body[first] >> 32)) ++last;
    for (std::uint32_t e = first; e < last; ++e) {
      const auto k = static_cast<std::uint32_t>(by_body[e] & 0xffffffffu);
      run_begin[2 * k + run_count[k]] = first;
      run_end[2 * k + run_count[k]] = last;
      ++run_count[k];
      capacity += last - first;
    }
    first = last;
  }
  begin = arena.AllocateArray<std::uint32_t>(count + 1);
  links = arena.AllocateArray<std::uint32_t>(capacity);
  std::uint32_t written = 0;
  for (std::uint32_t k = 0; k < count; ++k) {
    begin[k] = written;
    links[written++] = k;
    for (std::uint8_t run = 0; run < run_count[k]; ++run)
      for (std::uint32_t e = run_begin[2 * k + run]; e < run_end[2 * k + run]; ++e)
        links[written++] = static_cast<std::uint32_t>(by_body[e] & 0xffffffffu);
    std::sort(links + begin[k], links + written);
    written = static_cast<std::uint32_t>(std::unique(links + begin[k], links + written) - links);
  }
  begin[count] = written;
}

void BandedOrder(std::uint32_t count, const std::uint32_t* begin, const std::uint32_t* links,
                 std::uint32_t* order, std::uint32_t* degree, std::uint8_t* placed) {
  for (std::uint32_t i = 0; i < count; ++i) {
    degree[i] = begin[i + 1] - begin[i] - 1;
    placed[i] = 0;
  }
  std::uint32_t filled = 0;
  while (filled < count) {
    std::uint32_t start = count;
    for (std::uint32_t i = 0; i < count; ++i)
      if (!placed[i] && (start == count || degree[i] < degree[start])) start = i;
    placed[start] = 1;
    order[filled++] = start;
    for (std::uint32_t head = filled - 1; head < filled; ++head) {
      const std::uint32_t from = order[head];
      const std::uint32_t first_new = filled;
      for (std::uint32_t e = begin[from]; e < begin[from + 1]; ++e)
        if (!placed[links[e]]) placed[links[e]] = 1, order[filled++] = links[e];
      // Insertion sort by degree, stable (and no buffer to allocate, unlike std::stable_sort).
      for (std::uint32_t k = first_new + 1; k < filled; ++k)
        for (std::uint32_t m = k; m > first_new && degree[order[m]] < degree[order[m - 1]]; --m)
          std::swap(order[m], order[m - 1]);
    }
  }
  std::reverse(order, order + count);
}

}  // namespace strata
