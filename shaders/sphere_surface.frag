#version 330 core
// Ray-traced sphere imposter. Two outputs, blended rather than depth-tested:
//  0: linear depth (metres along the optical axis) of the sphere's nearest point, blended
//     with MIN into a target cleared to a huge value, which keeps the nearest sphere;
//  1: the length of the eye ray's chord through the sphere, blended with ADD: thickness;
//     or, with far_depth_output, the depth of the sphere's far point, blended with MAX:
//     the back of the fluid, when only surface particles are drawn.
// With per-target blend equations (GL 4.0) both come from one draw of the particles; on
// 3.3 the renderer draws twice, routing one output at a time. No gl_FragDepth and no depth
// buffer: MIN blending is the depth test.

in vec3 quad_point_view;
flat in vec3 sphere_center;

uniform float radius;
uniform bool far_depth_output;

layout(location = 0) out float linear_depth;
layout(location = 1) out float chord_length;

void main() {
  vec3 ray = normalize(quad_point_view);
  float along = dot(ray, sphere_center);
  // Squared distance from the centre to the ray, computed directly (not |c|^2 - along^2,
  // which cancels catastrophically for small spheres far away).
  vec3 closest = ray * along - sphere_center;
  float half_chord_sq = radius * radius - dot(closest, closest);
  if (half_chord_sq < 0.0) discard;
  float half_chord = sqrt(half_chord_sq);
  linear_depth = -ray.z * (along - half_chord);
  chord_length = far_depth_output ? -ray.z * (along + half_chord) : 2.0 * half_chord;
}
