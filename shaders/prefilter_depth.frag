#version 330 core
// A small linear Gaussian blur of the gap-closed depth, one axis per pass, weighted by
// coverage so no-fluid pixels never leak in. It band-limits the depth so the smoothing
// filter may read it with a stride of 2 pixels without aliasing the particle bumps: a
// quarter of the taps for wide kernels. (A linear Gaussian is exactly separable and
// isotropic; what leaves streaks in separable fluid filters are range weights, and those
// stay in the 2-D pass.)
//
// Pass 1 (horizontal): in rg = (depth, coverage), out rg = (sum w*c*depth, sum w*c).
// Pass 2 (vertical):   in rg = pass 1, out rg = (weighted mean depth, coverage of the pixel
//                      in `coverage_texture`), the layout the filters read.

uniform sampler2D depth_texture;
uniform sampler2D coverage_texture;  // pass 2: the gap-closed depth, for the coverage
uniform ivec2 direction;             // (1, 0) or (0, 1)
uniform float sigma_pixels;
uniform bool final_pass;

layout(location = 0) out vec2 result;

void main() {
  ivec2 size = textureSize(depth_texture, 0);
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  int reach = int(ceil(2.5 * sigma_pixels));
  float inverse_two_sigma_sq = 1.0 / (2.0 * sigma_pixels * sigma_pixels);
  vec2 sum = vec2(0.0);
  for (int i = -reach; i <= reach; ++i) {
    ivec2 p = pixel + i * direction;
    if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size))) continue;
    vec2 s = texelFetch(depth_texture, p, 0).rg;
    if (!final_pass) s = vec2(s.r * s.g, s.g);  // (depth, coverage) -> (c * depth, c)
    sum += exp(-float(i * i) * inverse_two_sigma_sq) * s;
  }
  if (!final_pass) {
    result = sum;
    return;
  }
  float coverage = texelFetch(coverage_texture, pixel, 0).g;
  result = coverage > 0.0 && sum.y > 0.0 ? vec2(sum.x / sum.y, 1.0) : vec2(0.0);
}
