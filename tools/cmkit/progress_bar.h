// A progress bar on stderr for long runs (`compile`, `info`, `demo` builds,
// `soak`).
#pragma once

#include <fmt/core.h>

#include <cstdio>
#include <string>
#include <utility>

namespace cmkit::cli {

/// Width of the bar in characters.
inline constexpr int kProgressBarWidth = 40;

/// A progress bar on stderr, redrawn only when it changes.
class ProgressBar {
 public:
  /// Draws "LABEL [###   ] done/total UNIT" when enabled.
  explicit ProgressBar(bool enabled, std::string label = "building", std::string unit = "entities")
      : enabled_(enabled), label_(std::move(label)), unit_(std::move(unit)) {}
  ~ProgressBar() { finish(); }
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;
  /// Draws `done` of `total`.
  void update(std::size_t done, std::size_t total) {
    if (!enabled_ || total == 0) return;
    const int filled = static_cast<int>(done * kProgressBarWidth / total);
    if (filled == lastFilled_ && done != total) return;
    lastFilled_ = filled;
    fmt::print(stderr, "\r{} [{}{}] {}/{} {}", label_, std::string(static_cast<std::size_t>(filled), '#'),
               std::string(static_cast<std::size_t>(kProgressBarWidth - filled), ' '), done, total, unit_);
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
  std::string label_;
  std::string unit_;
  bool drawn_ = false;
  int lastFilled_ = -1;
};

}  // namespace cmkit::cli
