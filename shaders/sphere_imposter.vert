#version 330 core
// One camera-facing triangle per particle, for an exact ray-traced sphere in the fragment
// shaders. Not gl_PointSize (llvmpipe caps it), and one triangle rather than an instanced
// quad: llvmpipe's per-triangle setup and binning run on one thread and dominate the cost
// of small spheres, so one triangle (30 % more fragments than a quad, half the setup) is
// the faster imposter. A plain draw of 3 vertices per particle that fetch their sphere
// centre from a buffer texture.
//
// The triangle lies in the plane through the sphere centre perpendicular to the eye ray and
// circumscribes the sphere's perspective silhouette.

uniform samplerBuffer centers_view;  // xyz = sphere centre in GL view space
uniform mat4 projection;
uniform float radius;

out vec3 quad_point_view;  // this vertex's view-space point; interpolates across the quad
flat out vec3 sphere_center;

// An equilateral triangle around the unit circle (its vertices are 2 from the centre).
const vec2 kCorners[3] = vec2[3](vec2(0.0, 2.0), vec2(-1.7320508, -1.0), vec2(1.7320508, -1.0));

void main() {
  vec3 center_view = texelFetch(centers_view, gl_VertexID / 3).xyz;
  vec2 corner = kCorners[gl_VertexID % 3];
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
