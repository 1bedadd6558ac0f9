// Progress: what a long command shows while it works. On a terminal, a bar redrawn in place at most ten
// times a second; anywhere else (a log, a pipe, CI) nothing until Finish, so logs stay one line a command.
// Finish prints the command's one-line summary either way. One thread (the command's own) calls it.
#pragma once

#include <chrono>
#include <cstddef>
#include <cstdio>
#include <functional>
#include <string>

namespace strata::bench {

/// How a worker reports its share done: `done` of `total` units.
using ProgressCallback = std::function<void(std::size_t done, std::size_t total)>;

class Progress {
 public:
  /// `label` names the command ("strata bench"), `unit` what is counted ("runs", "steps"). Draws on `out`
  /// when it is a terminal.
  Progress(std::string label, std::string unit, std::FILE* out = stderr);
  /// As above, `terminal` saying whether to draw (tests, and callers that know better), redrawn at most
  /// once per `redraw_interval`.
  Progress(std::string label, std::string unit, std::FILE* out, bool terminal,
           std::chrono::milliseconds redraw_interval = std::chrono::milliseconds(100));
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  bool terminal() const { return terminal_; }
  /// `done` of `total` units; redraws when the redraw interval has passed or the work is complete.
  void Update(std::size_t done, std::size_t total);
  /// A callback that forwards to Update (valid while this Progress lives).
  ProgressCallback Callback() {
    return [this](std::size_t done, std::size_t total) { Update(done, total); };
  }
  /// Clears the bar and prints "LABEL: SUMMARY (N.N s)" as one line; later calls do nothing.
  void Finish(const std::string& summary);
  /// Erases the bar (call before writing to the same terminal); the next Update draws it again.
  void Hide();

 private:
  void Draw(std::size_t done, std::size_t total);

  using Clock = std::chrono::steady_clock;
  std::string label_;
  std::string unit_;
  std::FILE* out_;
  bool terminal_;
  std::chrono::milliseconds redraw_interval_;
  bool drawn_ = false;
  bool finished_ = false;
  Clock::time_point start_ = Clock::now();
  Clock::time_point last_draw_{};
};

}  // namespace strata::bench
