// Shared by the 2-D depth filters: the kernel for a pixel and how taps are read.
//
// The kernel is a Gaussian whose sigma is a world length (a few particle radii) projected
// at the centre pixel's depth, truncated at 2.5 sigma and at max_radius_pixels (so the
// cost per pixel is bounded; a close-up gets a narrower kernel, not a slower one).
// Taps are exact texels of the prefiltered depth (prefilter_depth.frag), visited through
// `offsets`, a half-disc of integer offsets sorted by length, each used with its mirror
// image. Kernels of sigma >= 2 pixels step 2 pixels per offset unit: the prefilter has
// removed what a 2-pixel grid would alias, and a tap then stands for 4 pixels.
//
// (Sparse taps from mipmap levels were tried first: bilinear interpolation makes each tap
// piecewise linear in the pixel position, and the kinks, small in depth, showed up as a
// grid in the normals. Exact texels of a blurred image have no kinks.)

const int MAX_OFFSETS = 128;
uniform vec2 offsets[MAX_OFFSETS];   // half-disc integer offsets, sorted by length
uniform int offset_count;
uniform float offset_units_max;      // length of the longest offset

uniform sampler2D depth_texture;     // rg = (prefiltered depth m, coverage); 0 = no fluid
uniform float focal_pixels;
uniform float sigma_world;
uniform float max_radius_pixels;

struct Kernel {
  float window;                // radius in pixels; < 1 means "leave the pixel alone"
  float inverse_two_sigma_sq;  // per squared pixel
  float edge_weight;           // the Gaussian at the window's edge, subtracted from all taps
  int stride;                  // pixels per offset unit: 1 or 2
};

Kernel kernelAt(float center_depth) {
  Kernel k;
  float sigma = sigma_world * focal_pixels / center_depth;
  k.window = min(2.5 * sigma, min(max_radius_pixels, 2.0 * offset_units_max));
  // Every other pixel once sigma >= 2 pixels: a Gaussian sampled every sigma pixels still
  // sums to its integral within exp(-2 pi^2) (about 3e-9), and it quarters the taps.
  k.stride = k.window >= 5.0 ? 2 : 1;
  sigma = k.window / 2.5;
  k.inverse_two_sigma_sq = 1.0 / (2.0 * sigma * sigma);
  // Taps fade to zero at the window's edge: a tap entering the window as it grows with
  // depth must not add a step (steps in depth are what speckles normals).
  k.edge_weight = exp(-k.window * k.window * k.inverse_two_sigma_sq);
  return k;
}

// Weight of a tap at squared distance r_sq (pixels).
float tapWeight(Kernel k, float r_sq) {
  return max(exp(-r_sq * k.inverse_two_sigma_sq) - k.edge_weight, 0.0);
}

float centerDepth(ivec2 pixel) { return texelFetch(depth_texture, pixel, 0).r; }

// Fluid depth at `pixel`, 0 where there is none (or outside the image).
float depthAt(ivec2 pixel) {
  ivec2 size = textureSize(depth_texture, 0);
  if (any(lessThan(pixel, ivec2(0))) || any(greaterThanEqual(pixel, size))) return 0.0;
  vec2 value = texelFetch(depth_texture, pixel, 0).rg;
  return value.g > 0.0 ? value.r : 0.0;
}
