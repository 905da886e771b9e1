#pragma once
// How the fluid surface is smoothed and shaded. Lengths are in metres unless the name says
// "in radii" (multiples of the particle radius) or "pixels".

#include <Eigen/Core>
#include <cstdint>

namespace pbf {

enum class DepthFilter {
  NarrowRange,  // Truong & Yuksel, I3D 2018 (default)
  Bilateral,    // classic 2-D bilateral filter
  None,         // raw sphere depths (bumpy; for debugging and comparison)
};

struct RenderOptions {
  // --- depth smoothing ---
  DepthFilter filter = DepthFilter::NarrowRange;
  // Before smoothing, the see-through gaps between touching spheres (0.41 r wide at most)
  // are closed by an erosion towards the eye whose reach is this many particle radii
  // (see shaders/close_gaps.frag); 0 turns it off.
  float gap_closing_in_radii = 0.7f;
  // Gaussian sigma in world units, as a multiple of the particle radius; projected to pixels
  // at each pixel's depth. Bumps of spheres 2 radii apart are flattened by
  // exp(-sigma^2 k^2 / 2), k = pi / r: 1.5 radii leave 1e-5 of them. The ball test's mean
  // normal error: 11 deg at 1.0 r, 6.5 deg at 1.5 r, 6.2 deg at 2.0 r (for 1.8x the taps).
  float filter_sigma_in_radii = 1.5f;
  // Upper bound of the kernel radius (2.5 sigma) in pixels, at most 16: the cost per fluid
  // pixel grows with its square. Close-ups get a narrower kernel rather than a slower one.
  int max_filter_radius_pixels = 16;
  // Narrow range: samples more than threshold behind the centre (and their mirror images)
  // are ignored; samples more than threshold in front are clamped to clamp in front.
  float narrow_range_threshold_in_radii = 8.0f;  // the paper's range: ~1 to 10
  float narrow_range_clamp_in_radii = 1.0f;
  // Bilateral: Gaussian range sigma.
  float bilateral_depth_sigma_in_radii = 2.0f;

  // --- what is drawn ---
  // Draw only the particles with fewer than interior_neighbor_count neighbours: the hidden
  // interior costs nothing. Takes effect only when render() is given neighbour counts
  // (without them every particle is drawn). Thickness then comes from the path between
  // the front and back faces of the surface instead of every particle's chord (see
  // shaders/thickness_from_depths.frag). In a 20k-particle block about a fifth of the
  // particles are surface particles, and a frame costs ~30 % less CPU.
  bool surface_particles_only = true;
  std::uint32_t interior_neighbor_count = 24;

  // --- shading ---
  float refractive_index = 1.333f;
  float fresnel_f0 = 0.02f;  // reflectance of water at normal incidence
  // Beer-Lambert absorption per metre of thickness (red is absorbed most: water is blue).
  // Thickness is the sum of the spheres' chords, about half the fluid's (touching spheres
  // fill 52 % of a lattice), and the colour is exaggerated so a 10 cm body reads as water.
  Eigen::Vector3f absorption = Eigen::Vector3f(30.0f, 10.0f, 4.0f);
  // World direction towards the light (z up), need not be normalised.
  Eigen::Vector3f light_direction = Eigen::Vector3f(0.4f, 0.3f, 1.0f);
  float specular_strength = 0.6f;
  float specular_exponent = 200.0f;
  // Procedural background: a checkered floor at this height of the world frame, sky above.
  float floor_height = 0.0f;
  float floor_tile_size = 0.1f;
  // Background pixels get alpha 0 when false (the fluid can then be overlaid on something).
  bool draw_background = true;
};

}  // namespace pbf
