#version 330 core
// Classic 2-D bilateral depth filter: Gaussian in image space times Gaussian in depth
// difference. Kept as the option to compare the narrow-range filter against; same kernel
// and sampling (filter_kernel.glsl).

#include "filter_kernel.glsl"

uniform float depth_sigma;

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
  float inverse_two_depth_sigma_sq = 1.0 / (2.0 * depth_sigma * depth_sigma);
  float center_weight = tapWeight(k, 0.0);
  float sum = center_weight * center;
  float weight_sum = center_weight;
  for (int i = 0; i < offset_count; ++i) {
    ivec2 offset = ivec2(offsets[i]) * k.stride;
    float r_sq = float(offset.x * offset.x + offset.y * offset.y);
    if (r_sq > k.window * k.window) break;
    float spatial = tapWeight(k, r_sq);
    float a = depthAt(pixel + offset);
    float b = depthAt(pixel - offset);
    if (a > 0.0) {
      float w = spatial * exp(-(a - center) * (a - center) * inverse_two_depth_sigma_sq);
      sum += w * a;
      weight_sum += w;
    }
    if (b > 0.0) {
      float w = spatial * exp(-(b - center) * (b - center) * inverse_two_depth_sigma_sq);
      sum += w * b;
      weight_sum += w;
    }
  }
  smoothed_depth = sum / weight_sum;
}
