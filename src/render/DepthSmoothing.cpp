// Sphere depth -> a smooth fluid surface: gap and pinhole closing (close_gaps.frag), a
// light separable prefilter (prefilter_depth.frag), then the 2-D narrow-range
// (narrow_range_filter.frag) or bilateral (bilateral_filter.frag) filter.

#include <algorithm>
#include <cmath>

#include "RenderContext.h"

namespace pbf {

void RenderContext::resolveDepth(float gap_fraction, float focal, float radius) {
  // How far the erosion can matter: 1.5 reach at the nearest sphere (beyond that a
  // neighbour must be 2.25 radii nearer, another surface, not a gap), at most 6 pixels;
  // at least 2, to fill pinholes.
  const float reach =
      visible.nearest_depth > 0 ? gap_fraction * radius * focal / visible.nearest_depth : 0.0f;
  const int extent =
      gap_fraction <= 0 ? 0 : std::clamp(static_cast<int>(std::ceil(1.5f * reach)), 2, 6);
  close_gaps_program_.use();
  gl.Uniform1f(close_gaps_program_.uniform("focal_pixels"), focal);
  gl.Uniform1f(close_gaps_program_.uniform("radius"), radius);
  gl.Uniform1f(close_gaps_program_.uniform("gap_fraction"), std::max(gap_fraction, 1e-3f));
  gl.Uniform1i(close_gaps_program_.uniform("extent"), extent);
  const RenderTarget* source = raw_depth.get();
  if (extent > 0) {
    beginScreenPass(*gap_half, kClearDepth);  // read beyond the rectangle: no fluid
    gl.Uniform2i(close_gaps_program_.uniform("direction"), 1, 0);
    gl.Uniform1i(close_gaps_program_.uniform("final_pass"), 0);
    raw_depth->bindColorTexture(kUnitInput);
    drawFullscreen();
    source = gap_half.get();
  }
  beginScreenPass(*closed_depth);
  gl.Uniform2i(close_gaps_program_.uniform("direction"), 0, 1);
  gl.Uniform1i(close_gaps_program_.uniform("final_pass"), 1);
  source->bindColorTexture(kUnitInput);
  raw_depth->bindColorTexture(kUnitSecondInput);  // coverage
  drawFullscreen();
}

void RenderContext::smoothDepth(const RenderOptions& o, float focal, float radius) {
  prefilter_program_.use();
  beginScreenPass(*prefilter_half);
  gl.Uniform2i(prefilter_program_.uniform("direction"), 1, 0);
  gl.Uniform1i(prefilter_program_.uniform("final_pass"), 0);
  closed_depth->bindColorTexture(kUnitInput);
  drawFullscreen();
  beginScreenPass(*prefiltered_depth);
  gl.Uniform2i(prefilter_program_.uniform("direction"), 0, 1);
  gl.Uniform1i(prefilter_program_.uniform("final_pass"), 1);
  prefilter_half->bindColorTexture(kUnitInput);
  closed_depth->bindColorTexture(kUnitSecondInput);  // the coverage to keep
  drawFullscreen();

  const bool narrow = o.filter == DepthFilter::NarrowRange;
  const ShaderProgram& program = narrow ? narrow_range_program_ : bilateral_program_;
  beginScreenPass(*smoothed_depth);
  program.use();
  gl.Uniform1f(program.uniform("focal_pixels"), focal);
  gl.Uniform1f(program.uniform("sigma_world"), o.filter_sigma_in_radii * radius);
  gl.Uniform1f(program.uniform("max_radius_pixels"),
               static_cast<float>(o.max_filter_radius_pixels));
  if (narrow) {
    gl.Uniform1f(program.uniform("threshold"), o.narrow_range_threshold_in_radii * radius);
    gl.Uniform1f(program.uniform("clamp_distance"), o.narrow_range_clamp_in_radii * radius);
  } else {
    gl.Uniform1f(program.uniform("depth_sigma"), o.bilateral_depth_sigma_in_radii * radius);
  }
  prefiltered_depth->bindColorTexture(kUnitInput);
  drawFullscreen();
}

}  // namespace pbf
