#version 330 core
// Narrow-range depth filter (Truong & Yuksel, "A Narrow-Range Filter for Screen-Space
// Fluid Rendering", I3D 2018), full 2-D form.
//
// A Gaussian over a limited depth range around the centre pixel:
//  - a sample farther than `upper` (behind the surface, or no fluid at all) is dropped
//    together with its mirror image through the centre, so what remains stays symmetric and
//    cannot pull the mean towards the side that lost samples (the paper's bias correction);
//  - a sample nearer than `lower` (a surface in front) is clamped to `clamp_distance` in
//    front of the centre rather than trusted;
//  - accepted samples widen the range around themselves (dynamic range extension), so the
//    range follows a sloped surface outwards. Offsets are visited from the centre out.
// The kernel's sigma is a world length (a few particle radii) projected at this pixel's
// depth; far kernels are sampled with a stride so the cost stays bounded.

const int MAX_OFFSETS = 256;
uniform vec2 offsets[MAX_OFFSETS];  // half-plane integer offsets, sorted by length
uniform int offset_count;
uniform float offset_units_max;     // length of the longest offset

uniform sampler2D depth_texture;    // linear depth (m), 0 = no fluid
uniform float focal_pixels;
uniform float sigma_world;
uniform float max_radius_pixels;
uniform float threshold;
uniform float clamp_distance;

layout(location = 0) out float smoothed_depth;

float depthAt(ivec2 p, ivec2 size) {
  if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size))) return 0.0;
  return texelFetch(depth_texture, p, 0).r;
}

void main() {
  ivec2 size = textureSize(depth_texture, 0);
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float center = texelFetch(depth_texture, pixel, 0).r;
  if (center <= 0.0) {
    smoothed_depth = 0.0;
    return;
  }
  float sigma = sigma_world * focal_pixels / center;
  float window = min(2.5 * sigma, max_radius_pixels);
  if (window < 1.0) {
    smoothed_depth = center;
    return;
  }
  sigma = window / 2.5;
  float stride = max(1.0, ceil(window / offset_units_max));
  float inverse_two_sigma_sq = 1.0 / (2.0 * sigma * sigma);

  float upper = center + threshold;
  float lower = center - threshold;
  float clamped_in_front = center - clamp_distance;
  float sum = center;
  float weight_sum = 1.0;
  for (int i = 0; i < offset_count; ++i) {
    vec2 offset = offsets[i] * stride;
    float r_sq = dot(offset, offset);
    if (r_sq > window * window) break;
    ivec2 step = ivec2(offset);
    float a = depthAt(pixel + step, size);
    float b = depthAt(pixel - step, size);
    if (a <= 0.0 || b <= 0.0 || a > upper || b > upper) continue;  // pair dropped
    if (a < lower) {
      a = clamped_in_front;
    } else {
      upper = max(upper, a + threshold);
      lower = min(lower, a - threshold);
    }
    if (b < lower) {
      b = clamped_in_front;
    } else {
      upper = max(upper, b + threshold);
      lower = min(lower, b - threshold);
    }
    float weight = exp(-r_sq * inverse_two_sigma_sq);
    sum += weight * (a + b);
    weight_sum += 2.0 * weight;
  }
  smoothed_depth = sum / weight_sum;
}
