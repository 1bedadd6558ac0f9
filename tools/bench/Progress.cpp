#include "tools/bench/Progress.h"

#include <unistd.h>

#include <algorithm>
#include <utility>

namespace strata::bench {

namespace {
constexpr std::size_t kBarWidth = 30;
}  // namespace

Progress::Progress(std::string label, std::string unit, std::FILE* out)
    : Progress(std::move(label), std::move(unit), out, isatty(fileno(out)) != 0) {}

Progress::Progress(std::string label, std::string unit, std::FILE* out, bool terminal,
                   std::chrono::milliseconds redraw_interval)
    : label_(std::move(label)),
      unit_(std::move(unit)),
      out_(out),
      terminal_(terminal),
      redraw_interval_(redraw_interval) {}

Progress::~Progress() {
  Hide();
}

void Progress::Update(std::size_t done, std::size_t total) {
  if (!terminal_ || finished_) return;
  const Clock::time_point now = Clock::now();
  if (done < total && drawn_ && now - last_draw_ < redraw_interval_) return;
  last_draw_ = now;
  Draw(done, total);
}

void Progress::Draw(std::size_t done, std::size_t total) {
  const std::size_t filled = total == 0 ? kBarWidth : kBarWidth * std::min(done, total) / total;
  const double seconds = std::chrono::duration<double>(Clock::now() - start_).count();
  std::fprintf(out_, "\r\033[K%s [%s%s] %zu/%zu %s, %.1f s", label_.c_str(), std::string(filled, '#').c_str(),
               std::string(kBarWidth - filled, '.').c_str(), done, total, unit_.c_str(), seconds);
  std::fflush(out_);
  drawn_ = true;
}

void Progress::Hide() {
  if (!drawn_) return;
  std::fprintf(out_, "\r\033[K");
  std::fflush(out_);
  drawn_ = false;
}

void Progress::Finish(const std::string& summary) {
  if (finished_) return;
  Hide();
  finished_ = true;
  const double seconds = std::chrono::duration<double>(Clock::now() - start_).count();
  std::fprintf(out_, "%s: %s (%.1f s)\n", label_.c_str(), summary.c_str(), seconds);
  std::fflush(out_);
}

}  // namespace strata::bench
