#pragma once
// One self-overwriting progress line on stderr for long runs, at most a few per second,
// so a sweep that takes minutes shows it is alive (and how far it is) without flooding logs.

#include <chrono>
#include <cstdio>
#include <string>

namespace pbf_bench {

class Progress {
 public:
  explicit Progress(std::string label, bool enabled = true)
      : label_(std::move(label)), enabled_(enabled), start_(Clock::now()), last_(start_) {}
  ~Progress() { done(); }

  // fraction in [0, 1]; detail is appended (e.g. "t=0.21 s").
  void update(double fraction, const std::string& detail = "") {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (std::chrono::duration<double>(now - last_).count() < 0.5 && fraction < 1.0) return;
    last_ = now;
    std::fprintf(stderr, "\r  %-44s %5.1f%%  %-22s wall %6.1f s", label_.c_str(), 100.0 * fraction,
                 detail.c_str(), elapsed());
    std::fflush(stderr);
    printed_ = true;
  }
  void done() {
    if (enabled_ && printed_) std::fprintf(stderr, "\n");
    printed_ = false;
  }
  double elapsed() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  using Clock = std::chrono::steady_clock;
  std::string label_;
  bool enabled_;
  bool printed_ = false;
  Clock::time_point start_, last_;
};

}  // namespace pbf_bench
