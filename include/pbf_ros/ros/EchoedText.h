#pragma once
// Text a request brought, as the node echoes it in a log line or a reply: whole when short,
// else its start and its length. A probe's 1 MB ~emit shape came back as a 1 MB warning (and
// reply), a 200 KB scene name as a 600 KB log line: repeated, that fills a log disk.

#include <cstddef>
#include <string>

namespace pbf_ros {

constexpr std::size_t kEchoedChars = 200;

inline std::string echoed(const std::string& text, std::size_t max_chars = kEchoedChars) {
  if (text.size() <= max_chars) return text;
  return text.substr(0, max_chars) + "... (" + std::to_string(text.size()) + " characters)";
}

}  // namespace pbf_ros
