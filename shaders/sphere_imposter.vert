#version 330 core
// One camera-facing quad per particle (instanced; llvmpipe caps gl_PointSize, quads don't).
// The quad lies in the plane through the sphere centre perpendicular to the eye ray and is
// just big enough to cover the sphere's perspective silhouette, so the fragment shaders
// can ray-trace the exact sphere.

layout(location = 0) in vec3 center_view;  // per instance, GL view space

uniform mat4 projection;
uniform float radius;

out vec3 quad_point_view;   // this corner's view-space point; interpolates across the quad
flat out vec3 sphere_center;

void main() {
  vec2 corner = vec2(float(gl_VertexID & 1), float(gl_VertexID >> 1)) * 2.0 - 1.0;
  float distance_to_center = length(center_view);
  sphere_center = center_view;
  if (distance_to_center <= radius * 1.001) {
    // The eye is inside this sphere: nothing sensible to draw, send it off screen.
    quad_point_view = center_view;
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    return;
  }
  vec3 axis = center_view / distance_to_center;
  vec3 helper = abs(axis.y) < 0.99 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
  vec3 side = normalize(cross(axis, helper));
  vec3 up = cross(side, axis);
  // The silhouette cone (half-angle asin(r/d)) cut at distance d has radius r d / sqrt(d^2 - r^2).
  float half_size = radius * distance_to_center /
                    sqrt(distance_to_center * distance_to_center - radius * radius);
  quad_point_view = center_view + half_size * (corner.x * side + corner.y * up);
  gl_Position = projection * vec4(quad_point_view, 1.0);
}
