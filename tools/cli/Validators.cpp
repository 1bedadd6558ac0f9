#include "tools/cli/Validators.h"

#include <cmath>
#include <sstream>

namespace strata::cli {

CLI::Validator FiniteIn(double min, double max) {
  std::ostringstream description;
  description << "FINITE in [" << min << " - " << max << "]";
  return CLI::Validator(
      [min, max](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value)) return "not a number: " + text;
        if (!std::isfinite(value)) return "must be a finite number, got " + text;
        if (value < min || value > max) {
          std::ostringstream out;
          out << "must be in [" << min << ", " << max << "], got " << text;
          return out.str();
        }
        return {};
      },
      description.str());
}

}  // namespace strata::cli
