#version 330 core
// Shades the fluid over a procedural scene (checkered floor under a sky):
//  - reflection of the scene, weighted by Schlick's Fresnel term;
//  - refraction: the eye ray bends into the water (Snell) and picks up the floor or sky it
//    then meets, attenuated by Beer-Lambert absorption over the fluid thickness;
//  - a Blinn-Phong specular highlight of a directional light.
// Work is in the world frame (z up) so the floor and the light stay put as the camera moves.

uniform sampler2D depth_texture;      // smoothed linear depth (m), 0 = no fluid
uniform sampler2D normal_texture;     // GL view-space normals, w = 1 on fluid
uniform sampler2D thickness_texture;  // summed chord lengths (m)
uniform float focal_pixels;
uniform vec2 principal_point;
uniform mat3 world_from_view;
uniform vec3 eye_world;

uniform float refractive_index;
uniform float fresnel_f0;
uniform vec3 absorption;              // per metre
uniform vec3 light_direction;         // world, normalised, towards the light
uniform float specular_strength;
uniform float specular_exponent;
uniform float floor_height;
uniform float floor_tile_size;
uniform bool draw_background;

layout(location = 0) out vec4 color;

vec3 sky(vec3 direction) {
  float up = clamp(direction.z, -1.0, 1.0);
  vec3 horizon = vec3(0.82, 0.86, 0.90);
  vec3 zenith = vec3(0.32, 0.50, 0.78);
  vec3 base = mix(horizon, zenith, smoothstep(0.0, 0.8, up));
  float sun = pow(max(dot(direction, light_direction), 0.0), 400.0);
  return base + vec3(sun);
}

// Colour seen from `origin` along `direction`: the floor if the ray goes down to it.
vec3 scene(vec3 origin, vec3 direction) {
  if (direction.z < -1e-4 && origin.z > floor_height) {
    float t = (floor_height - origin.z) / direction.z;
    vec2 spot = origin.xy + t * direction.xy;
    vec2 tile = floor(spot / floor_tile_size);
    float checker = mod(tile.x + tile.y, 2.0);
    vec3 floor_color = mix(vec3(0.55, 0.53, 0.50), vec3(0.80, 0.78, 0.74), checker);
    floor_color *= 0.55 + 0.45 * max(light_direction.z, 0.0);
    // Fade towards the horizon colour with distance, which also hides checker aliasing.
    float fade = 1.0 - exp(-0.04 * t * t);
    return mix(floor_color, vec3(0.82, 0.86, 0.90), fade);
  }
  return sky(direction);
}

vec3 toDisplay(vec3 linear) { return pow(clamp(linear, 0.0, 1.0), vec3(1.0 / 2.2)); }

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec3 ray_view = normalize(vec3((vec2(pixel) + 0.5 - principal_point) / focal_pixels, -1.0));
  vec3 ray = world_from_view * ray_view;
  float depth = texelFetch(depth_texture, pixel, 0).r;
  if (depth <= 0.0) {
    color = draw_background ? vec4(toDisplay(scene(eye_world, ray)), 1.0) : vec4(0.0);
    return;
  }
  vec3 normal = world_from_view * texelFetch(normal_texture, pixel, 0).xyz;
  vec3 surface = eye_world + ray * (depth / -ray_view.z);
  float thickness = texelFetch(thickness_texture, pixel, 0).r;

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
