#version 330 core
// Classic 2-D bilateral depth filter: Gaussian in image space times Gaussian in depth
// difference. Kept as the option to compare the narrow-range filter against. Same kernel
// size and sampling as narrow_range_filter.frag.

const int MAX_OFFSETS = 256;
uniform vec2 offsets[MAX_OFFSETS];
uniform int offset_count;
uniform float offset_units_max;

uniform sampler2D depth_texture;    // linear depth (m), 0 = no fluid
uniform float focal_pixels;
uniform float sigma_world;
uniform float max_radius_pixels;
uniform float depth_sigma;

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
  float inverse_two_depth_sigma_sq = 1.0 / (2.0 * depth_sigma * depth_sigma);

  float sum = center;
  float weight_sum = 1.0;
  for (int i = 0; i < offset_count; ++i) {
    vec2 offset = offsets[i] * stride;
    float r_sq = dot(offset, offset);
    if (r_sq > window * window) break;
    float spatial = exp(-r_sq * inverse_two_sigma_sq);
    ivec2 step = ivec2(offset);
    float a = depthAt(pixel + step, size);
    float b = depthAt(pixel - step, size);
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
