#version 330 core
// Closes the see-through gaps between touching spheres before smoothing.
//
// Where spheres merely touch (radius = half the spacing), the eye sees between them into
// deeper layers: pixels a few radii deeper than their neighbours. A range-limited filter
// keeps or drops such samples pixel by pixel, and the resulting pixel-scale jitter of the
// smoothed depth is amplified into speckled normals (one pixel is a few millimetres, a
// particle radius a centimetre).
//
// The fix is a grey-scale erosion towards the eye with a paraboloid structuring element:
//   closed(p) = min over q of [ depth(q) + radius * |p - q|^2 / reach^2 ]
// with reach = gap_fraction * (the particle radius in pixels at p). A neighbour wins
// where it is nearer by more than the penalty, which a gap (a radius deep or more, and at
// most 0.41 r wide between four touching spheres) is, and a gently curved surface is not.
// Unlike a plain minimum over a disc of integer radius, the result changes continuously
// with the reach and does not depend on the direction: a disc whose radius jumps from 2 to
// 3 pixels where the depth crosses some value prints a band across the image.
// Pixels without fluid stay without fluid, so silhouettes keep their place.
//
// Also converts the sphere pass's output (nearest depth, a huge value where no sphere
// was drawn) to the (depth, coverage) pairs the later passes read.

const float kNoFluid = 1e29;      // the sphere pass clears to 1e30
uniform sampler2D depth_texture;  // r = linear depth (m), >= kNoFluid where no fluid
uniform float focal_pixels;
uniform float radius;             // particle radius (m)
uniform float gap_fraction;       // reach in particle radii
uniform int max_reach;            // pixels

layout(location = 0) out vec2 depth_and_coverage;

void main() {
  ivec2 size = textureSize(depth_texture, 0);
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float center = texelFetch(depth_texture, pixel, 0).r;
  if (center >= kNoFluid) {
    depth_and_coverage = vec2(0.0);
    return;
  }
  float reach = gap_fraction * radius * focal_pixels / center;
  if (reach < 0.25) {
    depth_and_coverage = vec2(center, 1.0);
    return;
  }
  // Beyond 1.5 reach a neighbour must be 2.25 radii nearer to matter: that is another
  // surface in front, which the narrow-range filter handles, not a gap.
  int extent = min(max_reach, int(ceil(1.5 * reach)));
  float penalty_per_sq_pixel = radius / (reach * reach);
  float nearest = center;
  for (int dy = -extent; dy <= extent; ++dy)
    for (int dx = -extent; dx <= extent; ++dx) {
      ivec2 p = pixel + ivec2(dx, dy);
      if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size))) continue;
      float d = texelFetch(depth_texture, p, 0).r;  // no fluid: 1e30, never the nearest
      nearest = min(nearest, d + penalty_per_sq_pixel * float(dx * dx + dy * dy));
    }
  depth_and_coverage = vec2(nearest, 1.0);
}
