#version 330 core
// The procedural scene as the camera sees it without fluid. Rendered only when the camera
// or the scene options change; every frame copies it and shades just the fluid on top.

#include "procedural_scene.glsl"

uniform float focal_pixels;
uniform vec2 principal_point;
uniform mat3 world_from_view;
uniform vec3 eye_world;
uniform bool draw_background;

layout(location = 0) out vec4 color;

void main() {
  if (!draw_background) {
    color = vec4(0.0);
    return;
  }
  vec3 ray_view = normalize(vec3((gl_FragCoord.xy - principal_point) / focal_pixels, -1.0));
  color = vec4(toDisplay(scene(eye_world, world_from_view * ray_view)), 1.0);
}
