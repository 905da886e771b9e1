// The procedural surroundings of the fluid, in the world frame (z up): a checkered floor
// at floor_height under a sky with a sun. Included by background.frag and composite.frag.

uniform vec3 light_direction;  // world, normalised, towards the light
uniform float floor_height;
uniform float floor_tile_size;

const vec3 kHorizon = vec3(0.82, 0.86, 0.90);

vec3 sky(vec3 direction) {
  float up = clamp(direction.z, -1.0, 1.0);
  vec3 zenith = vec3(0.32, 0.50, 0.78);
  vec3 base = mix(kHorizon, zenith, smoothstep(0.0, 0.8, up));
  float sun = pow(max(dot(direction, light_direction), 0.0), 400.0);
  return base + vec3(sun);
}

// Fraction of "light" tiles in a box of size `width` (in tiles) around `p`: the checker
// pattern integrated over a pixel's footprint (the box-filtered checkerboard), so neither
// the distant floor nor its image refracted through curved water alias into speckle.
float filteredChecker(vec2 p, vec2 width) {
  width = max(width, vec2(1e-4));
  vec2 integral = 2.0 * (abs(fract((p - 0.5 * width) * 0.5) - 0.5) -
                         abs(fract((p + 0.5 * width) * 0.5) - 0.5)) / width;
  return 0.5 - 0.5 * integral.x * integral.y;
}

// Colour seen from `origin` along `direction`: the floor if the ray goes down to it.
// Derivatives of the floor point across neighbouring pixels give the footprint, so call
// it where neighbouring pixels trace neighbouring rays.
vec3 scene(vec3 origin, vec3 direction) {
  float t = (floor_height - origin.z) / min(direction.z, -1e-4);
  vec2 spot = (origin.xy + t * direction.xy) / floor_tile_size;
  vec2 footprint = min(abs(dFdx(spot)) + abs(dFdy(spot)), vec2(4.0));
  if (direction.z < -1e-4 && origin.z > floor_height) {
    float checker = 1.0 - filteredChecker(spot + 0.5, footprint);
    vec3 floor_color = mix(vec3(0.50, 0.48, 0.45), vec3(0.78, 0.76, 0.72), checker);
    floor_color *= 0.55 + 0.45 * max(light_direction.z, 0.0);
    // Fade into the horizon with distance, which also hides the checker's aliasing.
    float fade = 1.0 - exp(-0.02 * t * t);
    return mix(floor_color, kHorizon, fade);
  }
  return sky(direction);
}

vec3 toDisplay(vec3 linear) { return pow(clamp(linear, 0.0, 1.0), vec3(1.0 / 2.2)); }
