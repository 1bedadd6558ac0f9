// BlockSkylineLdlt: the block L D L^T factorization of a symmetric matrix whose rows come in small blocks (a
// joint's rigid rows, at most six), stored by its envelope a block at a time: every row of a block starts at
// the block's first coupled column. D is block diagonal and kept inverted, so a solve's substitutions wait on
// one block after another, not one row after another (a chain's rows form one long dependency chain). In
// double, as SkylineLdlt. One solve's own object; not shared.
#pragma once

#include <cstdint>
#include <type_traits>

#include "physics/core/BlockArena.h"

namespace strata {

class BlockSkylineLdlt {
 public:
  static constexpr int kMaxBlock = 6;

  /// Room for `max_rows` rows in blocks holding `max_entries` envelope entries in all: a block of n rows
  /// whose first column is f and first row o takes n * (o - f + n).
  void Allocate(BlockArena& arena, std::uint32_t max_rows, std::uint32_t max_entries);

  /// Starts a new factorization with no rows.
  void Clear() { size_ = 0; }
  /// Appends a block of `rows` rows (1..kMaxBlock) whose envelope starts at column `first`, itself the
  /// first row of an earlier block or the new block's own first row. Returns the block's first row; the
  /// caller writes each of its rows through Row(), from `first` to the row itself (the lower triangle,
  /// zeros included), then calls FactorLastBlock.
  std::uint32_t AddBlock(std::uint32_t first, int rows);
  /// Row `row`, indexed by column.
  double* Row(std::uint32_t row) { return row_[row]; }
  /// Factors the block AddBlock added last, against the blocks before it, with `relative_extra` of each
  /// row's diagonal added to it (regularization). A pivot of the block's own L D L^T not above
  /// `relative_drop` of its row's diagonal is dropped: that combination of the block's rows takes no part in
  /// the solve.
  void FactorLastBlock(double relative_extra, double relative_drop);
  /// Solves the system for the rows added so far, in place (`x` holds the right-hand side on entry). Not
  /// from two threads at once: it works in the object's own scratch.
  void Solve(double* x) const;

  std::uint32_t size() const { return size_; }

  /// Calls `run` with `rows` (1..kMaxBlock) as a std::integral_constant, so a block's loops unroll.
  template <typename Run>
  static void WithBlockSize(int rows, Run&& run) {
    switch (rows) {
      case 1:
        return run(std::integral_constant<int, 1>{});
      case 2:
        return run(std::integral_constant<int, 2>{});
      case 3:
        return run(std::integral_constant<int, 3>{});
      case 4:
        return run(std::integral_constant<int, 4>{});
      case 5:
        return run(std::integral_constant<int, 5>{});
      default:
        return run(std::integral_constant<int, 6>{});
    }
  }

 private:
  template <int N>
  void FactorBlock(std::uint32_t block, double relative_extra, double relative_drop);

  double* lower_ = nullptr;         // the rows' envelopes, one after another
  double** row_ = nullptr;          // per row: its envelope indexed by column
  std::uint32_t* first_ = nullptr;  // per row: its block's first coupled column
  std::uint32_t* block_ = nullptr;  // per row: its block's first row
  std::uint32_t* end_ = nullptr;    // per row: one past its block's last row
  std::uint32_t* start_ = nullptr;  // per row: where its envelope starts in lower_ (size_ + 1 of them)
  double* work_ = nullptr;          // a solve's D^-1 z
  std::uint32_t size_ = 0;
};

}  // namespace strata
