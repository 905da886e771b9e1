#version 330 core
// Surface normals from the smoothed depth, in GL view space (x right, y up, z towards the
// eye). Each pixel is lifted to its view-space point; along x and along y the one-sided
// difference with the smaller depth change is used, so a silhouette or a step does not
// bend the normal of the surface it borders. Neighbours without fluid are never used.

uniform sampler2D depth_texture;  // smoothed linear depth (m), 0 = no fluid
uniform float focal_pixels;
uniform vec2 principal_point;     // window coordinates of the optical axis (width/2, height/2)

layout(location = 0) out vec4 normal_out;  // xyz = normal, w = 1 on fluid, all 0 elsewhere

vec3 viewPoint(ivec2 p, float depth) {
  vec2 xy = (vec2(p) + 0.5 - principal_point) / focal_pixels;
  return vec3(xy * depth, -depth);
}

float depthAt(ivec2 p, ivec2 size) {
  if (any(lessThan(p, ivec2(0))) || any(greaterThanEqual(p, size))) return 0.0;
  return texelFetch(depth_texture, p, 0).r;
}

// Tangent along `axis` (unit pixel step): the smaller-|dz| one-sided difference.
vec3 tangent(ivec2 p, float depth, vec3 point, ivec2 axis, ivec2 size) {
  float ahead = depthAt(p + axis, size);
  float behind = depthAt(p - axis, size);
  bool has_ahead = ahead > 0.0;
  bool has_behind = behind > 0.0;
  if (has_ahead && (!has_behind || abs(ahead - depth) <= abs(depth - behind)))
    return viewPoint(p + axis, ahead) - point;
  if (has_behind) return point - viewPoint(p - axis, behind);
  // An isolated pixel: assume it faces the eye.
  return vec3(vec2(axis) * depth / focal_pixels, 0.0);
}

void main() {
  ivec2 size = textureSize(depth_texture, 0);
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float depth = texelFetch(depth_texture, pixel, 0).r;
  if (depth <= 0.0) {
    normal_out = vec4(0.0);
    return;
  }
  vec3 point = viewPoint(pixel, depth);
  vec3 along_x = tangent(pixel, depth, point, ivec2(1, 0), size);
  vec3 along_y = tangent(pixel, depth, point, ivec2(0, 1), size);
  vec3 n = cross(along_x, along_y);
  // Degenerate tangents (parallel or zero) would normalise to NaN: face the eye instead.
  n = dot(n, n) > 1e-30 ? normalize(n) : normalize(-point);
  if (dot(n, point) > 0.0) n = -n;  // always face the eye
  normal_out = vec4(n, 1.0);
}
