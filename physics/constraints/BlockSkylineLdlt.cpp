#include "physics/constraints/BlockSkylineLdlt.h"

#include <algorithm>

#include "physics/constraints/SkylineLdlt.h"

namespace strata {

namespace {
// The inverse of the symmetric N x N block `matrix` (its lower triangle; N a compile-time size, so every
// loop unrolls) by its L D L^T without pivoting, written whole to rows[i][offset + j]. `extra` is added
// to the diagonal; a pivot not above `drop` of the row's diagonal is dropped (rows a loop of joints repeats)
// and its combination of the rows left out, rather than taken with a huge impulse.
// For 3 x 3 blocks (a point joint's rows), the adjugate over the determinant: a joint's factorization
// waits on the one before it along a chain, and this takes one division where the L D L^T takes three in a
// row. The same pivots decide which rows drop; a block that drops one goes the L D L^T way.
bool InvertThreeByThree(const double (&matrix)[BlockSkylineLdlt::kMaxBlock][BlockSkylineLdlt::kMaxBlock],
                        const double* diagonal, double extra, double drop, double* const* rows,
                        std::uint32_t offset) {
  const double a = matrix[0][0] + extra * diagonal[0], b = matrix[1][0], c = matrix[2][0];
  const double d = matrix[1][1] + extra * diagonal[1], e = matrix[2][1];
  const double f = matrix[2][2] + extra * diagonal[2];
  // Cofactors; the L D L^T's pivots are a, (a d - b^2) / a and det / (a d - b^2).
  const double c00 = d * f - e * e, c01 = c * e - b * f, c02 = b * e - c * d;
  const double c11 = a * f - c * c, c12 = b * c - a * e, c22 = a * d - b * b;
  const double determinant = a * c00 + b * c01 + c * c02;
  if (!(a > drop * diagonal[0] && c22 > drop * diagonal[1] * a && determinant > drop * diagonal[2] * c22))
    return false;
  const double inverse = 1.0 / determinant;
  const double entries[3][3] = {{c00, c01, c02}, {c01, c11, c12}, {c02, c12, c22}};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) rows[i][offset + j] = entries[i][j] * inverse;
  return true;
}

template <int N>
void InvertBlock(const double (&matrix)[BlockSkylineLdlt::kMaxBlock][BlockSkylineLdlt::kMaxBlock],
                 const double* diagonal, double extra, double drop, double* const* rows,
                 std::uint32_t offset) {
  if constexpr (N == 3)
    if (InvertThreeByThree(matrix, diagonal, extra, drop, rows, offset)) return;
  double lower[N][N];
  double pivot[N];
  double inverse_pivot[N];
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j < i; ++j) {
      double sum = matrix[i][j];
      for (int k = 0; k < j; ++k) sum -= lower[i][k] * pivot[k] * lower[j][k];
      lower[i][j] = sum * inverse_pivot[j];
    }
    double value = matrix[i][i] + extra * diagonal[i];
    for (int k = 0; k < i; ++k) value -= lower[i][k] * lower[i][k] * pivot[k];
    const bool kept = value > drop * diagonal[i];
    pivot[i] = kept ? value : 0.0;
    inverse_pivot[i] = kept ? 1.0 / value : 0.0;
  }
  // (L^-1)^T D^-1 L^-1.
  double unit_inverse[N][N];
  for (int j = 0; j < N; ++j) {
    for (int i = 0; i < j; ++i) unit_inverse[i][j] = 0.0;
    unit_inverse[j][j] = 1.0;
    for (int i = j + 1; i < N; ++i) {
      double sum = 0.0;
      for (int k = j; k < i; ++k) sum -= lower[i][k] * unit_inverse[k][j];
      unit_inverse[i][j] = sum;
    }
  }
  for (int i = 0; i < N; ++i)
    for (int j = 0; j <= i; ++j) {
      double sum = 0.0;
      for (int k = i; k < N; ++k) sum += unit_inverse[k][i] * inverse_pivot[k] * unit_inverse[k][j];
      rows[i][offset + j] = sum;
      rows[j][offset + i] = sum;
    }
}

// One block of a solve's first half: `rows` are the block's N rows, starting at row `block`, coupled from
// column `first`. Takes L z = b for the block (`x` holds z for the blocks before it) and writes z into `x`
// and y = D^-1 z into `y`: the inverted diagonal block waits only on this block's z.
template <int N>
void ForwardAndDiagonal(double* const* rows, double* x, double* y, std::uint32_t first, std::uint32_t block) {
  double z[N];
  for (int i = 0; i < N; ++i) z[i] = x[block + i];
  const auto substitute = [&](std::uint32_t k) {
    const double known = x[k];
    for (int i = 0; i < N; ++i) z[i] -= rows[i][k] * known;
  };
  if (block - first == N) {  // coupled with one block of its own size (a chain's): unrolled
    for (std::uint32_t k = 0; k < N; ++k) substitute(first + k);
  } else {
    for (std::uint32_t k = first; k < block; ++k) substitute(k);
  }
  for (int i = 0; i < N; ++i) x[block + i] = z[i];
  for (int i = 0; i < N; ++i) {
    double sum = 0.0;
    for (int j = 0; j < N; ++j) sum += rows[i][block + j] * z[j];
    y[block + i] = sum;
  }
}

// One block of L^T x = y, from the last block: the block's x is final, and its rows' share is taken off the
// earlier rows' y.
template <int N>
void Backward(double* const* rows, double* x, double* y, std::uint32_t first, std::uint32_t block) {
  double value[N];
  for (int i = 0; i < N; ++i) {
    value[i] = y[block + i];
    x[block + i] = value[i];
  }
  const auto substitute = [&](std::uint32_t k) {
    double sum = 0.0;
    for (int i = 0; i < N; ++i) sum += rows[i][k] * value[i];
    y[k] -= sum;
  };
  if (block - first == N) {  // as in ForwardAndDiagonal
    for (std::uint32_t k = 0; k < N; ++k) substitute(first + k);
  } else {
    for (std::uint32_t k = first; k < block; ++k) substitute(k);
  }
}

}  // namespace

void BlockSkylineLdlt::Allocate(BlockArena& arena, std::uint32_t max_rows, std::uint32_t max_entries) {
  lower_ = arena.AllocateArray<double>(max_entries);
  row_ = arena.AllocateArray<double*>(max_rows);
  first_ = arena.AllocateArray<std::uint32_t>(max_rows);
  block_ = arena.AllocateArray<std::uint32_t>(max_rows);
  end_ = arena.AllocateArray<std::uint32_t>(max_rows);
  start_ = arena.AllocateArray<std::uint32_t>(max_rows + 1);
  work_ = arena.AllocateArray<double>(max_rows);
  start_[0] = 0;
  size_ = 0;
}

std::uint32_t BlockSkylineLdlt::AddBlock(std::uint32_t first, int rows) {
  const std::uint32_t block = size_;
  const std::uint32_t end = block + static_cast<std::uint32_t>(rows);
  for (std::uint32_t r = block; r < end; ++r) {
    first_[r] = first;
    block_[r] = block;
    end_[r] = end;
    start_[r + 1] = start_[r] + (end - first);
    row_[r] = lower_ + start_[r] - first;
  }
  size_ = end;
  return block;
}

void BlockSkylineLdlt::FactorLastBlock(double relative_extra, double relative_drop) {
  const std::uint32_t block = block_[size_ - 1];
  BlockSkylineLdlt::WithBlockSize(static_cast<int>(size_ - block), [&](auto size) {
    FactorBlock<decltype(size)::value>(block, relative_extra, relative_drop);
  });
}

template <int N>
void BlockSkylineLdlt::FactorBlock(std::uint32_t block, double relative_extra, double relative_drop) {
  const std::uint32_t first = first_[block];
  double* const* const rows = row_ + block;
  double diagonal[kMaxBlock][kMaxBlock];
  double original[N];
  for (int i = 0; i < N; ++i) {
    for (int j = 0; j <= i; ++j) diagonal[i][j] = rows[i][block + j];
    original[i] = diagonal[i][i];
  }
  // Each row first as L D against the blocks before it: an entry waits on the earlier blocks' columns only
  // (within a block, L is the identity)...
  for (std::uint32_t c = first; c < block; ++c) {
    const std::uint32_t begin = std::max(first, first_[c]);
    if (begin == block_[c]) continue;
    for (int i = 0; i < N; ++i) rows[i][c] -= EnvelopeDot(rows[i], row_[c], begin, block_[c]);
  }
  // ...then scaled by each earlier block's inverted diagonal block, this block's diagonal block taking the
  // products off as it goes.
  for (std::uint32_t c = first; c < block; c = end_[c])
    BlockSkylineLdlt::WithBlockSize(static_cast<int>(end_[c] - c), [&](auto size) {
      constexpr int kSize = decltype(size)::value;
      double scaled[N][kSize];
      for (int i = 0; i < N; ++i)
        for (int j = 0; j < kSize; ++j) {
          const double* const inverse = row_[c + j];  // symmetric: the inverse's row j is its column j
          double sum = 0.0;
          for (int k = 0; k < kSize; ++k) sum += rows[i][c + k] * inverse[c + k];
          scaled[i][j] = sum;
        }
      for (int i = 0; i < N; ++i)
        for (int j = 0; j <= i; ++j) {
          double sum = 0.0;
          for (int k = 0; k < kSize; ++k) sum += rows[i][c + k] * scaled[j][k];
          diagonal[i][j] -= sum;
        }
      for (int i = 0; i < N; ++i)
        for (int k = 0; k < kSize; ++k) rows[i][c + k] = scaled[i][k];
    });
  InvertBlock<N>(diagonal, original, relative_extra, relative_drop, rows, block);
}

void BlockSkylineLdlt::Solve(double* x) const {
  // L z = b and y = D^-1 z, a block at a time (the rows of a block do not wait on each other), y kept apart
  // from z: the later blocks' substitutions need z.
  double* const y = work_;
  for (std::uint32_t block = 0; block < size_; block = end_[block])
    BlockSkylineLdlt::WithBlockSize(static_cast<int>(end_[block] - block), [&](auto size) {
      ForwardAndDiagonal<decltype(size)::value>(row_ + block, x, y, first_[block], block);
    });
  // L^T x = y, from the last block.
  for (std::uint32_t end = size_; end > 0;) {
    const std::uint32_t block = block_[end - 1];
    BlockSkylineLdlt::WithBlockSize(static_cast<int>(end - block), [&](auto size) {
      Backward<decltype(size)::value>(row_ + block, x, y, first_[block], block);
    });
    end = block;
  }
}

}  // namespace strata
