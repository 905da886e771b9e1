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
//   closed(p) = min over q of [ depth(q) + radius * |p - q|^2 / reach(q)^2 ]
// with reach = gap_fraction * (the particle radius in pixels at that depth). A neighbour
// wins where it is nearer by more than the penalty, which a gap (a radius deep or more, and
// at most 0.41 r wide between four touching spheres) is, and a gently curved surface is not.
// Unlike a plain minimum over a disc of integer radius, the result changes continuously
// with the reach and does not depend on the direction (a disc whose radius jumps from 2 to
// 3 pixels where the depth crosses some value prints a band across the image). Since
// |p - q|^2 = dx^2 + dy^2, the erosion is exactly separable: a pass along x, then along y.
//
// Some rays find no sphere at all, between the particles of a thin sheet: pinholes. A
// pixel without fluid becomes fluid when there is fluid on both sides of it within the
// search extent, along x or along y (a closing of the fluid mask, which leaves convex
// silhouettes where they are); it then takes its eroded depth like any other.
//
// Pass 1 (x): in r = sphere depth (>= kNoFluid where none), out r = eroded along x,
//             g = 1 where fluid is on both sides along x.
// Pass 2 (y): in rg = pass 1, out rg = (depth, coverage), the layout the later passes read;
//             `coverage_texture` is the sphere depth, for the mask.

const float kNoFluid = 1e29;         // the sphere pass clears to 1e30
uniform sampler2D depth_texture;
uniform sampler2D coverage_texture;  // pass 2: the sphere depth
uniform ivec2 direction;             // (1, 0) or (0, 1)
uniform bool final_pass;
uniform float focal_pixels;
uniform float radius;                // particle radius (m)
uniform float gap_fraction;          // reach in particle radii
uniform int extent;                  // pixels searched each way (0: just convert)

layout(location = 0) out vec2 result;

void main() {
  ivec2 size = textureSize(depth_texture, 0);
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  // penalty = radius * d^2 / reach^2 with reach = gap_fraction * radius * focal / depth.
  float penalty_scale = 1.0 / (gap_fraction * gap_fraction * radius * focal_pixels *
                               focal_pixels);
  vec2 here = texelFetch(depth_texture, pixel, 0).rg;
  float nearest = here.r;
  bool fluid_before = false, fluid_after = false;  // along this pass's axis
  for (int i = 1; i <= extent; ++i) {
    for (int side = -1; side <= 1; side += 2) {
      ivec2 p = pixel + side * i * direction;
      if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size))) continue;
      float d = texelFetch(depth_texture, p, 0).r;  // no fluid: 1e30, never the nearest
      nearest = min(nearest, d + penalty_scale * d * d * float(i * i));
      bool fluid = (final_pass ? texelFetch(coverage_texture, p, 0).r : d) < kNoFluid;
      if (side < 0) fluid_before = fluid_before || fluid;
      else fluid_after = fluid_after || fluid;
    }
  }
  bool enclosed = fluid_before && fluid_after;
  if (!final_pass) {
    result = vec2(nearest, enclosed ? 1.0 : 0.0);
    return;
  }
  bool fluid = texelFetch(coverage_texture, pixel, 0).r < kNoFluid || here.g > 0.5 || enclosed;
  result = fluid && nearest < kNoFluid ? vec2(nearest, 1.0) : vec2(0.0);
}
