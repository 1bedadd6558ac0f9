// Validators: CLI11 checks for numeric options that CLI11's own miss (its Range and PositiveNumber let NaN
// through: every comparison with NaN is false). Used while the CLI parses its arguments, on the main thread.
#pragma once

#include <CLI/CLI.hpp>

namespace strata::cli {

/// A finite number in [min, max].
CLI::Validator FiniteIn(double min, double max);

}  // namespace strata::cli
