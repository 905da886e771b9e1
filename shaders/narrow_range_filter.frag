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

#include "filter_kernel.glsl"

uniform float threshold;
uniform float clamp_distance;

layout(location = 0) out float smoothed_depth;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float center = centerDepth(pixel);
  if (center <= 0.0) {
    smoothed_depth = 0.0;
    return;
  }
  Kernel k = kernelAt(center);
  if (k.window < 1.0) {
    smoothed_depth = center;
    return;
  }
  float upper = center + threshold;
  float lower = center - threshold;
  float clamped_in_front = center - clamp_distance;
  float center_weight = tapWeight(k, 0.0);
  float sum = center_weight * center;
  float weight_sum = center_weight;
  for (int i = 0; i < offset_count; ++i) {
    ivec2 offset = ivec2(offsets[i]) * k.stride;
    float r_sq = float(offset.x * offset.x + offset.y * offset.y);
    if (r_sq > k.window * k.window) break;
    float a = depthAt(pixel + offset);
    float b = depthAt(pixel - offset);
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
    float weight = tapWeight(k, r_sq);
    sum += weight * (a + b);
    weight_sum += 2.0 * weight;
  }
  smoothed_depth = sum / weight_sum;
}
