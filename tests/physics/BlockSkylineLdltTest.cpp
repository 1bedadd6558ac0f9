// BlockSkylineLdlt against a dense solve: random block envelopes (blocks of 1 to 6 rows coupled with a few
// blocks before them) give the dense solution, and a block that repeats a row drops it and still solves the
// consistent system.
#include "physics/constraints/BlockSkylineLdlt.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <random>
#include <vector>

namespace strata {
namespace {

struct Envelope {
  std::vector<std::uint32_t> block_start;  // per block: its first row
  std::vector<int> block_rows;
  std::vector<std::uint32_t> block_first;  // per block: its first coupled column
  std::uint32_t rows = 0;
};

Envelope RandomEnvelope(std::mt19937& random, int blocks) {
  Envelope envelope;
  for (int b = 0; b < blocks; ++b) {
    const int rows = std::uniform_int_distribution<int>(1, BlockSkylineLdlt::kMaxBlock)(random);
    const int back = std::min(b, std::uniform_int_distribution<int>(0, 3)(random));
    envelope.block_start.push_back(envelope.rows);
    envelope.block_rows.push_back(rows);
    envelope.block_first.push_back(envelope.block_start[static_cast<std::size_t>(b - back)]);
    envelope.rows += static_cast<std::uint32_t>(rows);
  }
  return envelope;
}

// A symmetric, diagonally dominant matrix within the envelope.
Eigen::MatrixXd RandomMatrix(std::mt19937& random, const Envelope& envelope) {
  const auto n = static_cast<Eigen::Index>(envelope.rows);
  Eigen::MatrixXd matrix = Eigen::MatrixXd::Zero(n, n);
  std::uniform_real_distribution<double> entry(-1.0, 1.0);
  for (std::size_t b = 0; b < envelope.block_start.size(); ++b)
    for (int i = 0; i < envelope.block_rows[b]; ++i) {
      const auto row = static_cast<Eigen::Index>(envelope.block_start[b]) + i;
      for (auto column = static_cast<Eigen::Index>(envelope.block_first[b]); column < row; ++column)
        matrix(row, column) = matrix(column, row) = entry(random);
    }
  for (Eigen::Index i = 0; i < n; ++i) matrix(i, i) = matrix.row(i).cwiseAbs().sum() + 0.5;
  return matrix;
}

std::vector<double> FactorAndSolve(BlockArena& arena, const Envelope& envelope, const Eigen::MatrixXd& matrix,
                                   const Eigen::VectorXd& rhs) {
  std::uint32_t entries = 0;
  for (std::size_t b = 0; b < envelope.block_start.size(); ++b)
    entries += static_cast<std::uint32_t>(envelope.block_rows[b]) *
               (envelope.block_start[b] + static_cast<std::uint32_t>(envelope.block_rows[b]) -
                envelope.block_first[b]);
  BlockSkylineLdlt ldlt;
  ldlt.Allocate(arena, envelope.rows, entries);
  for (std::size_t b = 0; b < envelope.block_start.size(); ++b) {
    const std::uint32_t start = ldlt.AddBlock(envelope.block_first[b], envelope.block_rows[b]);
    EXPECT_EQ(start, envelope.block_start[b]);
    for (std::uint32_t row = start; row < start + static_cast<std::uint32_t>(envelope.block_rows[b]); ++row)
      for (std::uint32_t column = envelope.block_first[b]; column <= row; ++column)
        ldlt.Row(row)[column] = matrix(row, column);
    ldlt.FactorLastBlock(0.0, 1e-12);
  }
  std::vector<double> x(rhs.data(), rhs.data() + rhs.size());
  ldlt.Solve(x.data());
  return x;
}

TEST(BlockSkylineLdlt, SolvesRandomBlockEnvelopesAsADenseSolveDoes) {
  std::mt19937 random(42);
  BlockArena arena;
  for (int trial = 0; trial < 50; ++trial) {
    const Envelope envelope = RandomEnvelope(random, 1 + trial % 17);
    const Eigen::MatrixXd matrix = RandomMatrix(random, envelope);
    const Eigen::VectorXd rhs = Eigen::VectorXd::Random(matrix.rows());
    const Eigen::VectorXd expected = matrix.ldlt().solve(rhs);
    const std::vector<double> x = FactorAndSolve(arena, envelope, matrix, rhs);
    for (Eigen::Index i = 0; i < expected.size(); ++i)
      ASSERT_NEAR(x[static_cast<std::size_t>(i)], expected(i), 1e-9) << "trial " << trial << " row " << i;
  }
}

TEST(BlockSkylineLdlt, ARepeatedRowIsDroppedAndTheConsistentSystemStillSolved) {
  // The repeated row in a block of three (a point joint's, inverted in closed form unless a pivot drops)
  // and in a block of four.
  for (const int rows : {3, 4}) {
    std::mt19937 random(7);
    BlockArena arena;
    Envelope envelope;
    envelope.block_start = {0, 3, 3 + static_cast<std::uint32_t>(rows)};
    envelope.block_rows = {3, rows, 2};
    envelope.block_first = {0, 0, 3};
    envelope.rows = 5 + static_cast<std::uint32_t>(rows);
    Eigen::MatrixXd matrix = RandomMatrix(random, envelope);
    // Row 5 repeats row 4 (a loop of joints holding the same thing twice): singular.
    matrix.row(5) = matrix.row(4);
    matrix.col(5) = matrix.col(4);
    const Eigen::VectorXd solution = Eigen::VectorXd::Random(matrix.rows());
    const Eigen::VectorXd rhs = matrix * solution;
    const std::vector<double> x = FactorAndSolve(arena, envelope, matrix, rhs);
    const Eigen::VectorXd found = Eigen::Map<const Eigen::VectorXd>(x.data(), matrix.rows());
    EXPECT_TRUE(found.allFinite()) << rows;
    EXPECT_LT((matrix * found - rhs).norm(), 1e-9 * rhs.norm()) << rows;
    // The repeated row takes no part: the pair's combined unknown is all that is solved for.
    EXPECT_NEAR(found(4) + found(5), solution(4) + solution(5), 1e-9) << rows;
  }
}

}  // namespace
}  // namespace strata
