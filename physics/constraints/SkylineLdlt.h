// SkylineLdlt: the L D L^T factorization (no square roots) of a symmetric matrix stored by its envelope: row
// r holds its entries from the first column it couples with to the diagonal, so the rows of a chain of joints
// or a stack's contacts (banded once ordered) cost rows x band^2. The exact contact solve and the exact joint
// solve both factor and solve through it. In double: a heavy body on light links spreads the eigenvalues over
// about six decades, which a float factorization does not survive. One solve's own object; not shared.
#pragma once

#include <cstdint>

#include "physics/core/BlockArena.h"

namespace strata {

/// Sum of x[k] y[k] for k in [begin, end): an envelope row against a row or a vector, in two chains so that
/// the adds overlap.
inline double EnvelopeDot(const double* x, const double* y, std::uint32_t begin, std::uint32_t end) {
  double even = 0.0, odd = 0.0;
  std::uint32_t k = begin;
  for (; k + 1 < end; k += 2) {
    even += x[k] * y[k];
    odd += x[k + 1] * y[k + 1];
  }
  if (k < end) even += x[k] * y[k];
  return even + odd;
}

class SkylineLdlt {
 public:
  /// Room for `max_rows` rows holding `max_entries` envelope entries in all, taken from `arena`.
  void Allocate(BlockArena& arena, std::uint32_t max_rows, std::uint32_t max_entries);

  /// Starts a new factorization with no rows.
  void Clear() { size_ = 0; }
  /// Appends row size() whose envelope starts at column `first` (<= the row) and returns it, indexed by
  /// column and valid from `first` to the row itself: the caller writes the matrix's row into it (zeros
  /// included), then calls FactorLastRow.
  double* AddRow(std::uint32_t first);
  /// Factors the row AddRow returned last, against the rows before it, with `diagonal_extra` added to its
  /// diagonal (a row's softness or regularization). A pivot not above `drop_at` is dropped: the row then
  /// takes no part in the solve (its unknown comes out 0). Returns whether the pivot was kept.
  bool FactorLastRow(double diagonal_extra, double drop_at);
  /// Solves L D L^T x = b for the rows added so far, in place (`x` holds b on entry).
  void Solve(double* x) const;

  std::uint32_t size() const { return size_; }

 private:
  double* lower_ = nullptr;             // the rows' envelopes, one after another
  double* inverse_diagonal_ = nullptr;  // 1 / D, 0 for a dropped row
  double** row_ = nullptr;              // per row: its envelope indexed by column (valid from first_)
  std::uint32_t* first_ = nullptr;      // per row: its envelope's first column
  std::uint32_t* start_ = nullptr;      // per row: where its envelope starts in lower_ (size_ + 1 of them)
  std::uint32_t size_ = 0;
};

}  // namespace strata
