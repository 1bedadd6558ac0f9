#include "tools/accuracy/AccuracyReport.h"

#include <stb/stb_easy_font.h>
#include <stb/stb_image_write.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <sstream>

#include "physics/core/OutputFile.h"

namespace strata::accuracy {

namespace {

// Errors this small are exact for the report's purposes (and for the log axis).
constexpr double kErrorFloor = 1e-5;

std::unique_ptr<AccuracyEngine> MakeEngine(const std::string& name) {
  if (name == "strata") return MakeStrataEngine();
  if (name == "bullet") return MakeBulletEngine();
  return nullptr;
}

bool SameSetting(const AccuracySetting& a, const AccuracySetting& b) {
  return a.dt == b.dt && a.substeps == b.substeps && a.velocity_iterations == b.velocity_iterations &&
         a.relax_iterations == b.relax_iterations && a.linear_cast == b.linear_cast &&
         a.exact_small_islands == b.exact_small_islands;
}

// A plain RGB canvas for the plot.
class Canvas {
 public:
  Canvas(int width, int height) : width_(width), height_(height), rgb_(3 * width * height, 255) {}
  void Set(int x, int y, const std::array<std::uint8_t, 3>& color) {
    if (x < 0 || y < 0 || x >= width_ || y >= height_) return;
    std::copy(color.begin(), color.end(), rgb_.begin() + 3 * (y * width_ + x));
  }
  void Line(double x0, double y0, double x1, double y1, const std::array<std::uint8_t, 3>& color) {
    const int steps = static_cast<int>(std::max(std::abs(x1 - x0), std::abs(y1 - y0))) + 1;
    for (int i = 0; i <= steps; ++i) {
      const double t = static_cast<double>(i) / steps;
      Set(static_cast<int>(std::lround(x0 + t * (x1 - x0))),
          static_cast<int>(std::lround(y0 + t * (y1 - y0))), color);
    }
  }
  void Dot(double cx, double cy, int radius, const std::array<std::uint8_t, 3>& color, bool filled) {
    for (int dy = -radius; dy <= radius; ++dy)
      for (int dx = -radius; dx <= radius; ++dx) {
        const int d2 = dx * dx + dy * dy;
        if (d2 <= radius * radius && (filled || d2 >= (radius - 1) * (radius - 1)))
          Set(static_cast<int>(cx) + dx, static_cast<int>(cy) + dy, color);
      }
  }
  // stb_easy_font gives quads of 4 vertices (x, y, z, colour) per glyph stroke.
  void Text(int x, int y, const std::string& text, const std::array<std::uint8_t, 3>& color) {
    static char buffer[60000];
    const int quads = stb_easy_font_print(static_cast<float>(x), static_cast<float>(y),
                                          const_cast<char*>(text.c_str()), nullptr, buffer, sizeof(buffer));
    const auto* vertices = reinterpret_cast<const float*>(buffer);
    for (int q = 0; q < quads; ++q) {
      const float* v = vertices + q * 16;
      for (int py = static_cast<int>(v[1]); py < static_cast<int>(v[9]); ++py)
        for (int px = static_cast<int>(v[0]); px < static_cast<int>(v[8]); ++px) Set(px, py, color);
    }
  }
  std::string Png() const {
    std::string out;
    stbi_write_png_to_func(
        [](void* context, void* data, int size) {
          static_cast<std::string*>(context)->append(static_cast<const char*>(data), size);
        },
        &out, width_, height_, 3, rgb_.data(), width_ * 3);
    return out;
  }

 private:
  int width_, height_;
  std::vector<std::uint8_t> rgb_;
};

std::string Format(double value) {
  if (!std::isfinite(value)) return "inf";
  char text[32];
  std::snprintf(text, sizeof(text), value != 0.0 && std::abs(value) < 1e-3 ? "%.2e" : "%.4f", value);
  return text;
}

}  // namespace

Result<std::vector<AccuracyRecord>> RunAccuracySuite(const std::vector<AccuracyCase>& cases,
                                                     const std::vector<AccuracySetting>& settings,
                                                     const std::vector<std::string>& engines, int timing_runs,
                                                     const bench::ProgressCallback& progress) {
  std::vector<AccuracyRecord> records;
  const std::size_t passes = static_cast<std::size_t>(std::max(timing_runs, 1));
  const std::size_t total = passes * cases.size() * engines.size() * settings.size();
  std::size_t visited = 0;
  const AccuracySetting defaults = DefaultAccuracySetting();
  // Whole passes over the suite, each run's time the least of its passes: a burst of noise on a shared
  // machine then lands on one pass of a few runs, not on one engine's whole front.
  for (int pass = 0; pass < std::max(timing_runs, 1); ++pass) {
    std::size_t next = 0;
    for (const AccuracyCase& c : cases)
      for (const std::string& engine_name : engines)
        for (const AccuracySetting& setting : settings) {
          if (progress) progress(visited, total);
          ++visited;
          std::unique_ptr<AccuracyEngine> engine = MakeEngine(engine_name);
          if (!engine)
            return MakeError(ErrorCode::kInvalidArgument, "no engine '" + engine_name + "' in this build");
          if (!engine->Runs(setting)) continue;
          Result<CaseOutcome> outcome = c.run(*engine, setting);
          if (!outcome)
            return MakeError(outcome.error().code, c.name + " at " + setting.name + " on " + engine_name +
                                                       ": " + outcome.error().message);
          if (pass > 0) {
            AccuracyRecord& record = records[next++];
            record.wall_ms = std::min(record.wall_ms, engine->step_ms());
            // Both engines are deterministic; a run that is not shows as its worst error.
            if (!(outcome->error <= record.error)) record.error = outcome->error;
            record.finite = record.finite && outcome->finite;
            record.passed = record.finite && record.error <= c.tolerance;
            continue;
          }
          AccuracyRecord record;
          record.case_name = c.name;
          record.setting = setting.name;
          record.engine = engine_name;
          record.error = outcome->error;
          record.tolerance = c.tolerance;
          record.wall_ms = engine->step_ms();
          record.finite = outcome->finite;
          record.passed = outcome->finite && outcome->error <= c.tolerance;
          record.is_default = SameSetting(setting, defaults);
          records.push_back(record);
        }
  }
  return records;
}

std::vector<AccuracyRecord> ParetoFront(const std::vector<AccuracyRecord>& records,
                                        const std::string& case_name, const std::string& engine) {
  std::vector<AccuracyRecord> runs;
  for (const AccuracyRecord& r : records)
    if (r.case_name == case_name && r.engine == engine && std::isfinite(r.error)) runs.push_back(r);
  std::sort(runs.begin(), runs.end(), [](const AccuracyRecord& a, const AccuracyRecord& b) {
    return a.wall_ms != b.wall_ms ? a.wall_ms < b.wall_ms : a.error < b.error;
  });
  std::vector<AccuracyRecord> front;
  double best = std::numeric_limits<double>::infinity();
  for (const AccuracyRecord& r : runs)
    if (std::max(r.error, kErrorFloor) < best) {
      best = std::max(r.error, kErrorFloor);
      front.push_back(r);
    }
  return front;
}

namespace {
// Whether run `s` is as accurate as `b` (errors under `floor` count as equal); Covers: and no slower.
bool AsAccurate(const AccuracyRecord& s, const AccuracyRecord& b, double floor) {
  return std::max(s.error, floor) <= std::max(b.error, floor);
}
bool Covers(const AccuracyRecord& s, const AccuracyRecord& b, double floor) {
  return s.wall_ms <= b.wall_ms && AsAccurate(s, b, floor);
}
}  // namespace

bool FrontAtOrBelow(const std::vector<AccuracyRecord>& strata, const std::vector<AccuracyRecord>& bullet,
                    double floor) {
  return std::all_of(bullet.begin(), bullet.end(), [&](const AccuracyRecord& b) {
    return std::any_of(strata.begin(), strata.end(),
                       [&](const AccuracyRecord& s) { return Covers(s, b, floor); });
  });
}

std::vector<FrontGap> FrontGaps(const std::vector<AccuracyRecord>& records, const std::string& case_name,
                                double floor) {
  std::vector<AccuracyRecord> strata;
  for (const AccuracyRecord& r : records)
    if (r.case_name == case_name && r.engine == "strata" && std::isfinite(r.error)) strata.push_back(r);
  std::vector<FrontGap> gaps;
  for (const AccuracyRecord& b : ParetoFront(records, case_name, "bullet")) {
    if (std::any_of(strata.begin(), strata.end(),
                    [&](const AccuracyRecord& s) { return Covers(s, b, floor); }))
      continue;
    FrontGap gap{b, std::nullopt};
    for (const AccuracyRecord& s : strata)
      if (AsAccurate(s, b, floor) && (!gap.strata || s.wall_ms < gap.strata->wall_ms)) gap.strata = s;
    gaps.push_back(gap);
  }
  return gaps;
}

bool OnlyFailingRunsUncovered(const std::vector<FrontGap>& gaps) {
  return !gaps.empty() &&
         std::none_of(gaps.begin(), gaps.end(), [](const FrontGap& gap) { return gap.bullet.passed; });
}

Status WriteAccuracyJson(const std::vector<AccuracyRecord>& records, const std::vector<AccuracyCase>& cases,
                         const std::filesystem::path& path) {
  nlohmann::json document;
  nlohmann::json case_list = nlohmann::json::array();
  for (const AccuracyCase& c : cases) {
    nlohmann::json entry = {{"name", c.name}, {"what", c.what}, {"unit", c.unit}, {"tolerance", c.tolerance}};
    const auto strata = ParetoFront(records, c.name, "strata");
    const auto bullet = ParetoFront(records, c.name, "bullet");
    if (!bullet.empty()) {
      entry["front_at_or_below_bullet"] = FrontAtOrBelow(strata, bullet, c.tolerance * 0.1);
      entry["only_failing_bullet_runs_uncovered"] =
          OnlyFailingRunsUncovered(FrontGaps(records, c.name, c.tolerance * 0.1));
    }
    case_list.push_back(entry);
  }
  nlohmann::json runs = nlohmann::json::array();
  for (const AccuracyRecord& r : records)
    runs.push_back({{"case", r.case_name},
                    {"setting", r.setting},
                    {"engine", r.engine},
                    {"error", std::isfinite(r.error) ? nlohmann::json(r.error) : nlohmann::json(nullptr)},
                    {"wall_ms", r.wall_ms},
                    {"finite", r.finite},
                    {"passed", r.passed},
                    {"default", r.is_default}});
  document["cases"] = case_list;
  document["runs"] = runs;
  return WriteOutputFile(path, document.dump(2) + "\n");
}

Status WriteAccuracyMarkdown(const std::vector<AccuracyRecord>& records,
                             const std::vector<AccuracyCase>& cases, const std::filesystem::path& path) {
  std::ostringstream out;
  out << "# Accuracy against run time\n\nError (in the case's unit), stepping wall time in ms, and pass (at "
         "or "
         "below the tolerance) for each case, setting and engine. `*` marks the world's default setting.\n";
  for (const AccuracyCase& c : cases) {
    out << "\n## " << c.name << "\n\n"
        << c.what << " (" << c.unit << ", pass <= " << Format(c.tolerance)
        << ")\n\n| setting | engine | error | ms | pass |\n|---|---|---|---|---|\n";
    for (const AccuracyRecord& r : records) {
      if (r.case_name != c.name) continue;
      out << "| " << r.setting << (r.is_default ? " *" : "") << " | " << r.engine << " | " << Format(r.error)
          << " | " << Format(r.wall_ms) << " | " << (r.passed ? "yes" : "**no**") << " |\n";
    }
    const auto bullet = ParetoFront(records, c.name, "bullet");
    if (bullet.empty()) continue;
    const std::vector<FrontGap> gaps = FrontGaps(records, c.name, c.tolerance * 0.1);
    out << "\nStrata's Pareto front is " << (gaps.empty() ? "at or below" : "**not** at or below")
        << " Bullet's.\n";
    for (const FrontGap& gap : gaps) {
      out << "- Bullet " << gap.bullet.setting << " (error " << Format(gap.bullet.error) << ", "
          << Format(gap.bullet.wall_ms) << " ms, " << (gap.bullet.passed ? "passes" : "fails the tolerance")
          << "): ";
      if (!gap.strata) {
        out << "no Strata run is as accurate\n";
        continue;
      }
      out << "the cheapest Strata run as accurate is " << gap.strata->setting << " (error "
          << Format(gap.strata->error) << ", " << Format(gap.strata->wall_ms) << " ms, "
          << Format(gap.strata->wall_ms / gap.bullet.wall_ms) << "x the time)\n";
    }
  }
  return WriteOutputFile(path, out.str());
}

Status WriteAccuracyPlot(const std::vector<AccuracyRecord>& records, const std::vector<AccuracyCase>& cases,
                         const std::filesystem::path& path) {
  constexpr int kPanel = 300, kColumns = 4, kMargin = 40;
  const int rows = (static_cast<int>(cases.size()) + kColumns - 1) / kColumns;
  Canvas canvas(kColumns * kPanel, rows * kPanel + 30);
  canvas.Text(
      10, 10,
      "error (log, y) against stepping time (log ms, x); filled = Pareto front; blue Strata, red Bullet",
      {0, 0, 0});
  const std::array<std::uint8_t, 3> kStrata{30, 90, 200}, kBullet{200, 40, 40}, kAxis{120, 120, 120};
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const AccuracyCase& c = cases[i];
    const int left = static_cast<int>(i % kColumns) * kPanel + kMargin;
    const int top = static_cast<int>(i / kColumns) * kPanel + 30 + 20;
    const int width = kPanel - kMargin - 10, height = kPanel - kMargin - 30;
    double min_ms = 1e30, max_ms = 0.0, min_error = 1e30, max_error = 0.0;
    for (const AccuracyRecord& r : records) {
      if (r.case_name != c.name || !std::isfinite(r.error)) continue;
      min_ms = std::min(min_ms, std::max(r.wall_ms, 1e-3));
      max_ms = std::max(max_ms, std::max(r.wall_ms, 1e-3));
      min_error = std::min(min_error, std::max(r.error, kErrorFloor));
      max_error = std::max(max_error, std::max(r.error, kErrorFloor));
    }
    min_error = std::min(min_error, c.tolerance), max_error = std::max(max_error, c.tolerance);
    canvas.Text(left - 30, top - 14, c.name, {0, 0, 0});
    canvas.Line(left, top + height, left + width, top + height, kAxis);
    canvas.Line(left, top, left, top + height, kAxis);
    if (max_ms <= 0.0) continue;
    const double lx0 = std::log10(min_ms) - 0.1, lx1 = std::log10(max_ms) + 0.1;
    const double ly0 = std::log10(min_error) - 0.2, ly1 = std::log10(max_error) + 0.2;
    auto x_of = [&](double ms) {
      return left + (std::log10(std::max(ms, 1e-3)) - lx0) / (lx1 - lx0) * width;
    };
    auto y_of = [&](double error) {
      return top + height - (std::log10(std::max(error, kErrorFloor)) - ly0) / (ly1 - ly0) * height;
    };
    // The tolerance as a dashed line.
    for (int x = 0; x < width; x += 6)
      canvas.Line(left + x, y_of(c.tolerance), left + x + 3, y_of(c.tolerance), kAxis);
    canvas.Text(left + 2, static_cast<int>(y_of(c.tolerance)) - 9, "pass", kAxis);
    canvas.Text(left, top + height + 4, Format(min_ms) + " ms", kAxis);
    canvas.Text(left + width - 50, top + height + 4, Format(max_ms) + " ms", kAxis);
    canvas.Text(left - 38, top, Format(max_error), kAxis);
    for (const char* engine : {"bullet", "strata"}) {
      const auto color = std::string(engine) == "strata" ? kStrata : kBullet;
      for (const AccuracyRecord& r : records)
        if (r.case_name == c.name && r.engine == engine && std::isfinite(r.error))
          canvas.Dot(x_of(r.wall_ms), y_of(r.error), 3, color, false);
      const auto front = ParetoFront(records, c.name, engine);
      for (std::size_t k = 0; k < front.size(); ++k) {
        canvas.Dot(x_of(front[k].wall_ms), y_of(front[k].error), 3, color, true);
        if (k > 0)
          canvas.Line(x_of(front[k - 1].wall_ms), y_of(front[k - 1].error), x_of(front[k].wall_ms),
                      y_of(front[k].error), color);
      }
    }
  }
  return WriteOutputFile(path, canvas.Png());
}

}  // namespace strata::accuracy
