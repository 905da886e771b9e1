#version 330 core
// Ray-traced sphere imposter: writes the linear depth (metres along the optical axis) of
// the nearest point of the sphere, and the matching window depth so the depth test keeps
// the nearest sphere. The second channel is coverage (1 here, 0 where nothing is drawn).

in vec3 quad_point_view;
flat in vec3 sphere_center;

uniform mat4 projection;
uniform float radius;

layout(location = 0) out vec2 depth_and_coverage;

void main() {
  vec3 ray = normalize(quad_point_view);
  float along = dot(ray, sphere_center);
  // Squared distance from the centre to the ray, computed directly (not |c|^2 - along^2,
  // which cancels catastrophically for small spheres far away).
  vec3 closest = ray * along - sphere_center;
  float half_chord_sq = radius * radius - dot(closest, closest);
  if (half_chord_sq < 0.0) discard;
  vec3 hit = ray * (along - sqrt(half_chord_sq));
  depth_and_coverage = vec2(-hit.z, 1.0);
  vec4 clip = projection * vec4(hit, 1.0);
  gl_FragDepth = 0.5 * (clip.z / clip.w) + 0.5;
}
