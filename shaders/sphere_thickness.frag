#version 330 core
// Additive thickness: each sphere adds the length of the eye ray's chord through it.

in vec3 quad_point_view;
flat in vec3 sphere_center;

uniform float radius;

layout(location = 0) out float chord_length;

void main() {
  vec3 ray = normalize(quad_point_view);
  vec3 closest = ray * dot(ray, sphere_center) - sphere_center;
  float half_chord_sq = radius * radius - dot(closest, closest);
  if (half_chord_sq < 0.0) discard;
  chord_length = 2.0 * sqrt(half_chord_sq);
}
