#pragma once
// Numbers from a tool's command line, read whole: "abc", "1.5x", "nan", "inf" or a value out
// of range is an error naming the option and what it got (std::atof and std::stoi read
// "nan" as NaN and "12abc" as 12, and a bad --spacing used to be ignored or to exhaust memory).

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace pbf_tools {

// A finite number > 0, or std::invalid_argument naming `option`.
inline double finitePositive(const std::string& option, const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v) || !(v > 0.0))
    throw std::invalid_argument(option + " expects a finite number > 0, got '" + text + "'");
  return v;
}

// An integer in [lo, hi], or std::invalid_argument naming `option`.
inline long integerIn(const std::string& option, const std::string& text, long lo, long hi) {
  char* end = nullptr;
  errno = 0;
  const long v = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || v < lo || v > hi)
    throw std::invalid_argument(option + " expects an integer in [" + std::to_string(lo) + ", " +
                                std::to_string(hi) + "], got '" + text + "'");
  return v;
}

}  // namespace pbf_tools
