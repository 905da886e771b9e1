#version 330 core
// Thickness when only the surface particles were drawn: the ray's path from the nearest
// front face to the farthest back face of the surface spheres, in the same units as the
// summed chords of every particle (which cover pi/6 = 52 % of the path through a lattice
// of touching spheres), so the absorption looks the same either way. Air between two
// separate bodies on one ray counts as fluid here: a fair price for drawing ~5x fewer
// spheres in a bulky scene.

const float kNoFluid = 1e29;
const float kSphereFill = 0.5235988;  // pi / 6
uniform sampler2D near_texture;       // nearest front face (m), 1e30 = no fluid
uniform sampler2D far_texture;        // farthest back face (m), 0 = no fluid

layout(location = 0) out float thickness;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float near = texelFetch(near_texture, pixel, 0).r;
  float far = texelFetch(far_texture, pixel, 0).r;
  thickness = near < kNoFluid ? kSphereFill * max(far - near, 0.0) : 0.0;
}
