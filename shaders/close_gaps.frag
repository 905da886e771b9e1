#version 330 core
// Closes the see-through gaps between touching spheres before smoothing.
//
// Where spheres merely touch (radius = half the spacing), the eye sees between them into
// deeper layers: single pixels a few radii deeper than their neighbours. A range-limited
// filter keeps or drops such samples pixel by pixel, and the resulting pixel-scale jitter of
// the smoothed depth is amplified into speckled normals (one pixel is a few millimetres, a
// particle radius a centimetre). Taking the nearest fluid depth within a fraction of the
// projected particle radius fills those gaps (the widest, between four touching spheres,
// has an inscribed radius of (sqrt(2) - 1) r = 0.41 r) and leaves the silhouette alone:
// pixels without fluid stay without fluid.

uniform sampler2D depth_texture;  // rg = (linear depth m, coverage), level 0
uniform float focal_pixels;
uniform float radius;             // particle radius (m)
uniform float gap_fraction;       // search radius in particle radii
uniform int max_reach;            // pixels

layout(location = 0) out vec2 depth_and_coverage;

void main() {
  ivec2 size = textureSize(depth_texture, 0);
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec2 center = texelFetch(depth_texture, pixel, 0).rg;
  if (center.g <= 0.0) {
    depth_and_coverage = vec2(0.0);
    return;
  }
  int reach = min(max_reach, int(ceil(gap_fraction * radius * focal_pixels / center.r)));
  float nearest = center.r;
  for (int dy = -reach; dy <= reach; ++dy)
    for (int dx = -reach; dx <= reach; ++dx) {
      if (dx * dx + dy * dy > reach * reach) continue;
      ivec2 p = clamp(pixel + ivec2(dx, dy), ivec2(0), size - 1);
      vec2 s = texelFetch(depth_texture, p, 0).rg;
      if (s.g > 0.0) nearest = min(nearest, s.r);
    }
  depth_and_coverage = vec2(nearest, 1.0);
}
