#pragma once
// Everything FluidRenderer keeps on the GPU, and the passes that use it. One class, its
// methods defined by stage in their own files:
//   RenderContext.cpp   programs, targets, buffers; shared helpers
//   SpherePass.cpp      particles -> nearest depth and thickness (sphere imposters)
//   DepthSmoothing.cpp  gap closing, prefilter, narrow-range or bilateral filter
//   Shading.cpp         normals, cached background, composite
//   Readback.cpp        GPU images -> top-down CPU images of RenderOutput
// Internal to pbf_render: the public face is FluidRenderer.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "GlFunctions.h"
#include "ParticleCulling.h"
#include "RenderTarget.h"
#include "ShaderProgram.h"
#include "pbf_ros/render/GlBackend.h"
#include "pbf_ros/render/RenderCamera.h"
#include "pbf_ros/render/RenderOptions.h"
#include "pbf_ros/render/RenderOutput.h"

namespace pbf {

// Texture units, bound to each program's samplers once at set-up: a pass reads its main
// input (depth of some stage) on unit 0 and a second one (normals, coverage, far depth) on
// unit 1.
constexpr int kUnitInput = 0, kUnitSecondInput = 1, kUnitThickness = 2, kUnitCenters = 3,
              kUnitBackground = 4;

constexpr GLfloat kClearDepth[4] = {1e30f, 0, 0, 0};  // "no fluid" for MIN blending
constexpr GLfloat kClearZero[4] = {0, 0, 0, 0};

class RenderContext {
 public:
  // Loads GL from the backend's current context and builds every program (throws naming
  // the shader file and quoting the compiler on failure).
  RenderContext(const GlBackend& backend, const std::string& shader_dir);
  ~RenderContext();
  RenderContext(const RenderContext&) = delete;
  RenderContext& operator=(const RenderContext&) = delete;

  // Sizes the targets the request needs.
  void resize(int width, int height, const RenderRequest& request, const RenderOptions& o);

  // --- SpherePass.cpp ---
  // What the sphere pass's second output accumulates (sphere_surface.frag).
  enum class SecondOutput {
    Chords,    // summed chord lengths, ADD-blended into `thickness`: every particle
    FarDepth,  // depth of the farthest sphere back face, MAX-blended into `far_depth`:
               // surface particles only, thickness resolved afterwards as far - near
  };
  void uploadParticles();
  // Depth target cleared to "no fluid", then MIN-blended (output 0), surface particles.
  void drawSphereDepth(const Eigen::Matrix4f& projection, float radius);
  // The second output alone (output 1 routed to the target's only attachment).
  void drawSecondOutput(const Eigen::Matrix4f& projection, float radius, SecondOutput second);
  // Both outputs from one draw (GL 4.0: a blend equation per target).
  void drawSphereDepthAndSecond(const Eigen::Matrix4f& projection, float radius,
                                SecondOutput second);
  // thickness = (far - near) * pi / 6 after a FarDepth pass.
  void resolveThicknessFromDepths();

  // --- DepthSmoothing.cpp ---
  // (depth, coverage) pairs in closed_depth from the sphere depth, gaps and pinholes
  // closed (close_gaps.frag); gap_fraction 0 only converts.
  void resolveDepth(float gap_fraction, float focal, float radius);
  // closed_depth -> prefiltered_depth -> smoothed_depth.
  void smoothDepth(const RenderOptions& o, float focal, float radius);

  // --- Shading.cpp ---
  void computeNormals(const RenderTarget& surface_depth, float focal,
                      const Eigen::Vector2f& principal);
  // Redraws the procedural background only when the camera or scene options changed.
  void updateBackground(const RenderCamera& camera, const RenderOptions& o, float focal,
                        const Eigen::Vector2f& principal);
  void composite(const RenderTarget& surface_depth, const RenderCamera& camera,
                 const RenderOptions& o, float focal, const Eigen::Vector2f& principal,
                 float radius);

  // --- Readback.cpp ---
  void readBack(const RenderRequest& request, const RenderTarget& surface_depth,
                RenderOutput& out);

  GlFunctions gl;
  VisibleParticles visible;  // this frame's particles, filled by selectVisibleParticles
  std::unique_ptr<RenderTarget> raw_depth, far_depth, gap_half, closed_depth, prefilter_half,
      prefiltered_depth, thickness, smoothed_depth, normals, background, color;

 private:
  void drawFullscreen() { gl.DrawArrays(GL_TRIANGLES, 0, 3); }
  // One triangle per sphere; see sphere_imposter.vert.
  void drawSpheres(GLsizei count) {
    if (count > 0) gl.DrawArrays(GL_TRIANGLES, 0, 3 * count);
  }
  // Clears the whole target, then limits drawing to the fluid's bounding rectangle: the
  // screen-space passes cost nothing outside the fluid.
  void beginScreenPass(const RenderTarget& target, const GLfloat* clear_value = kClearZero);
  void limitToFluid();

  void setSphereUniforms(const Eigen::Matrix4f& projection, float radius, SecondOutput second);
  RenderTarget& secondTarget(SecondOutput second) {
    return second == SecondOutput::FarDepth ? *far_depth : *thickness;
  }
  GLsizei secondCount(SecondOutput second) const {
    return static_cast<GLsizei>(second == SecondOutput::FarDepth
                                    ? visible.surface_count
                                    : visible.view_positions.size());
  }
  void setSceneUniforms(const ShaderProgram& p, const RenderCamera& camera,
                        const RenderOptions& o, float focal, const Eigen::Vector2f& principal);
  template <typename T>
  void readRowsTopDown(const RenderTarget& target, GLenum format, GLenum type, int channels,
                       std::vector<T>& scratch, std::vector<T>& out);

  ShaderProgram sphere_program_, close_gaps_program_, prefilter_program_,
      narrow_range_program_, bilateral_program_, thickness_program_, normals_program_,
      background_program_, composite_program_;
  // Draws depth and thickness in one pass (both targets attached), when GL >= 4.0.
  GLuint sphere_framebuffer_ = 0;
  // Sphere centres: a buffer object read by the imposter vertex shader as a buffer texture.
  GLuint particle_buffer_ = 0, particle_texture_ = 0, empty_vao_ = 0;
  std::vector<float> background_key_;  // what the cached background was drawn for
  std::vector<std::uint8_t> byte_scratch_;
  std::vector<float> float_scratch_, normal_scratch_;
};

}  // namespace pbf
