#version 330 core
// Shades the fluid pixels (the rest of the image is the cached background):
//  - reflection of the procedural scene, weighted by Schlick's Fresnel term;
//  - refraction: the eye ray bends into the water (Snell) and picks up the floor or sky it
//    then meets, attenuated by Beer-Lambert absorption over the fluid thickness;
//  - a Blinn-Phong specular highlight of a directional light.
// Work is in the world frame (z up) so the floor and the light stay put as the camera moves.

#include "procedural_scene.glsl"

uniform sampler2D depth_texture;      // smoothed linear depth (m), 0 = no fluid
uniform sampler2D normal_texture;     // GL view-space normals, w = 1 on fluid
uniform sampler2D thickness_texture;  // summed chord lengths (m), mipmapped
uniform sampler2D background_texture; // the scene without fluid, display-ready
uniform float focal_pixels;
uniform vec2 principal_point;
uniform mat3 world_from_view;
uniform vec3 eye_world;

uniform float refractive_index;
uniform float fresnel_f0;
uniform vec3 absorption;              // per metre
uniform float specular_strength;
uniform float specular_exponent;
uniform float radius;                 // particle radius (m)

layout(location = 0) out vec4 color;

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  float depth = texelFetch(depth_texture, pixel, 0).r;
  if (depth <= 0.0) {
    color = texelFetch(background_texture, pixel, 0);
    return;
  }
  vec3 ray_view = normalize(vec3((gl_FragCoord.xy - principal_point) / focal_pixels, -1.0));
  vec3 ray = world_from_view * ray_view;
  vec3 normal = world_from_view * texelFetch(normal_texture, pixel, 0).xyz;
  vec3 surface = eye_world + ray * (depth / -ray_view.z);
  // Chord sums through a particle lattice streak along its channels; averaging over about
  // a particle diameter (a mipmap level, bilinear) leaves the thickness of the body.
  float particle_pixels = 2.0 * radius * focal_pixels / depth;
  float thickness = textureLod(thickness_texture,
                               gl_FragCoord.xy / vec2(textureSize(thickness_texture, 0)),
                               max(0.0, log2(particle_pixels))).r;

  float cos_incidence = clamp(dot(-ray, normal), 0.0, 1.0);
  float fresnel = fresnel_f0 + (1.0 - fresnel_f0) * pow(1.0 - cos_incidence, 5.0);

  vec3 reflected = scene(surface, reflect(ray, normal));
  vec3 bent = refract(ray, normal, 1.0 / refractive_index);
  vec3 transmitted = vec3(0.0);
  if (dot(bent, bent) > 0.0) {
    transmitted = scene(surface, bent) * exp(-absorption * thickness);
  } else {
    fresnel = 1.0;  // total internal reflection
  }

  vec3 halfway = normalize(light_direction - ray);
  float specular = specular_strength * pow(max(dot(normal, halfway), 0.0), specular_exponent);
  vec3 shaded = mix(transmitted, reflected, fresnel) + vec3(specular);
  color = vec4(toDisplay(shaded), 1.0);
}
