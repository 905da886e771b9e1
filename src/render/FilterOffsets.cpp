#include "FilterOffsets.h"

#include <algorithm>
#include <array>

namespace pbf {

std::vector<float> halfDiscOffsets(int radius) {
  std::vector<std::array<int, 2>> points;
  for (int y = 0; y <= radius; ++y)
    for (int x = -radius; x <= radius; ++x) {
      const int length_sq = x * x + y * y;
      if (length_sq == 0 || length_sq > radius * radius) continue;
      if (y == 0 && x < 0) continue;  // the mirror of (-x, 0)
      points.push_back({x, y});
    }
  std::stable_sort(points.begin(), points.end(), [](const auto& a, const auto& b) {
    return a[0] * a[0] + a[1] * a[1] < b[0] * b[0] + b[1] * b[1];
  });
  std::vector<float> flat;
  flat.reserve(points.size() * 2);
  for (const auto& p : points) {
    flat.push_back(static_cast<float>(p[0]));
    flat.push_back(static_cast<float>(p[1]));
  }
  return flat;
}

}  // namespace pbf
