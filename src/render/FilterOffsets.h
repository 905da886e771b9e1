#pragma once
// Sample offsets of the 2-D depth filters: one of each mirrored pair (+o, -o), i.e. the
// integer points of a half-disc, sorted from the centre outwards (the narrow-range filter's
// range extension must meet near samples before far ones).

#include <vector>

namespace pbf {

// Returns x0, y0, x1, y1, ... for every integer (x, y) with 0 < x^2 + y^2 <= radius^2 and
// (y > 0 or (y == 0 and x > 0)), ordered by length (ties in a fixed order).
std::vector<float> halfDiscOffsets(int radius);

}  // namespace pbf
