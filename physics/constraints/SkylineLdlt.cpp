#include "physics/constraints/SkylineLdlt.h"

#include <algorithm>

namespace strata {

void SkylineLdlt::Allocate(BlockArena& arena, std::uint32_t max_rows, std::uint32_t max_entries) {
  lower_ = arena.AllocateArray<double>(max_entries);
  inverse_diagonal_ = arena.AllocateArray<double>(max_rows);
  row_ = arena.AllocateArray<double*>(max_rows);
  first_ = arena.AllocateArray<std::uint32_t>(max_rows);
  start_ = arena.AllocateArray<std::uint32_t>(max_rows + 1);
  start_[0] = 0;
  size_ = 0;
}

double* SkylineLdlt::AddRow(std::uint32_t first) {
  const std::uint32_t r = size_++;
  first_[r] = first;
  start_[r + 1] = start_[r] + (r - first + 1);
  // Indexed by column, so the inner loops are plain dot products over contiguous memory.
  row_[r] = lower_ + start_[r] - first;
  return row_[r];
}

bool SkylineLdlt::FactorLastRow(double diagonal_extra, double drop_at) {
  const std::uint32_t r = size_ - 1;
  double* const row = row_[r];
  const std::uint32_t first = first_[r];
  // The row is first worked out as L(r, c) D(c) (each entry waits only on the dot product before it), then
  // scaled by 1 / D(c), which no other entry of the row waits on.
  for (std::uint32_t c = first; c < r; ++c)
    row[c] -= EnvelopeDot(row, row_[c], std::max(first, first_[c]), c);
  double diagonal = row[r] + diagonal_extra;
  for (std::uint32_t c = first; c < r; ++c) {
    const double scaled = row[c] * inverse_diagonal_[c];
    diagonal -= scaled * row[c];
    row[c] = scaled;
  }
  row[r] = 1.0;
  const bool kept = diagonal > drop_at;
  inverse_diagonal_[r] = kept ? 1.0 / diagonal : 0.0;
  return kept;
}

void SkylineLdlt::Solve(double* x) const {
  for (std::uint32_t r = 0; r < size_; ++r) x[r] -= EnvelopeDot(row_[r], x, first_[r], r);
  for (std::uint32_t r = 0; r < size_; ++r) x[r] *= inverse_diagonal_[r];
  for (std::uint32_t r = size_; r-- > 0;) {
    const double* const row = row_[r];
    const double value = x[r];
    for (std::uint32_t k = first_[r]; k < r; ++k) x[k] -= row[k] * value;
  }
}

}  // namespace strata
