// A progress bar on stderr for long builds (`compile`, `info`, `demo`).
#pragma once

#include <fmt/core.h>

#include <cstdio>
#include <string>

namespace cmkit::cli {

/// Width of the bar in characters.
inline constexpr int kProgressBarWidth = 40;

/// A progress bar on stderr, redrawn only when it changes.
class ProgressBar {
 public:
  explicit ProgressBar(bool enabled) : enabled_(enabled) {}
  ~ProgressBar() { finish(); }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  /// Draws `done` of `total` entities.
  void update(std::size_t done, std::size_t total) {
    if (!enabled_ || total == 0) return;
    const int filled = static_cast<int>(done * kProgressBarWidth / total);
    if (filled == lastFilled_ && done != total) return;
    lastFilled_ = filled;
    fmt::print(stderr, "\rbuilding [{}{}] {}/{} entities", std::string(static_cast<std::size_t>(filled), '#'),
               std::string(static_cast<std::size_t>(kProgressBarWidth - filled), ' '), done, total);
    std::fflush(stderr);
    drawn_ = true;
  }
  /// Erases the bar.
  void finish() {
    if (drawn_) fmt::print(stderr, "\r\033[K");
    drawn_ = false;
  }

 private:
  bool enabled_;
  bool drawn_ = false;
  int lastFilled_ = -1;
};

}  // namespace cmkit::cli
