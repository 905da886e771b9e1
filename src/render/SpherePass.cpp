// Particles -> nearest sphere depth and thickness, with ray-traced sphere imposters
// (sphere_imposter.vert, sphere_surface.frag). No depth buffer: MIN blending keeps the
// nearest sphere, ADD sums chords, MAX keeps the farthest back face.

#include <stdexcept>

#include "RenderContext.h"

namespace pbf {
namespace {

GLenum secondEquation(RenderContext::SecondOutput second) {
  return second == RenderContext::SecondOutput::FarDepth ? GL_MAX : GL_FUNC_ADD;
}

}  // namespace

void RenderContext::uploadParticles() {
  gl.BindBuffer(GL_TEXTURE_BUFFER, particle_buffer_);
  gl.BufferData(GL_TEXTURE_BUFFER, visible.view_positions.size() * sizeof(Eigen::Vector4f),
                visible.view_positions.data(), GL_STREAM_DRAW);
  gl.ActiveTexture(GL_TEXTURE0 + kUnitCenters);
  gl.BindTexture(GL_TEXTURE_BUFFER, particle_texture_);
  gl.TexBuffer(GL_TEXTURE_BUFFER, GL_RGBA32F, particle_buffer_);
}

void RenderContext::setSphereUniforms(const Eigen::Matrix4f& projection, float radius,
                                      SecondOutput second) {
  sphere_program_.use();
  gl.UniformMatrix4fv(sphere_program_.uniform("projection"), 1, GL_FALSE, projection.data());
  gl.Uniform1f(sphere_program_.uniform("radius"), radius);
  gl.Uniform1i(sphere_program_.uniform("far_depth_output"),
               second == SecondOutput::FarDepth ? 1 : 0);
}

void RenderContext::drawSphereDepth(const Eigen::Matrix4f& projection, float radius) {
  raw_depth->bindForDrawing();
  const GLenum outputs[] = {GL_COLOR_ATTACHMENT0};
  gl.DrawBuffers(1, outputs);
  gl.Disable(GL_SCISSOR_TEST);
  gl.ClearBufferfv(GL_COLOR, 0, kClearDepth);
  gl.Enable(GL_BLEND);
  gl.BlendFunc(GL_ONE, GL_ONE);
  gl.BlendEquation(GL_MIN);
  setSphereUniforms(projection, radius, SecondOutput::Chords);
  drawSpheres(static_cast<GLsizei>(visible.surface_count));
  gl.Disable(GL_BLEND);
}

void RenderContext::drawSecondOutput(const Eigen::Matrix4f& projection, float radius,
                                     SecondOutput second) {
  RenderTarget& target = secondTarget(second);
  target.bindForDrawing();
  const GLenum outputs[] = {GL_NONE, GL_COLOR_ATTACHMENT0};
  gl.DrawBuffers(2, outputs);
  gl.Disable(GL_SCISSOR_TEST);
  gl.ClearBufferfv(GL_COLOR, 1, kClearZero);
  gl.Enable(GL_BLEND);
  gl.BlendFunc(GL_ONE, GL_ONE);
  gl.BlendEquation(secondEquation(second));
  setSphereUniforms(projection, radius, second);
  drawSpheres(secondCount(second));
  gl.Disable(GL_BLEND);
}

void RenderContext::drawSphereDepthAndSecond(const Eigen::Matrix4f& projection, float radius,
                                             SecondOutput second) {
  // With FarDepth both outputs need only the surface particles; with Chords every
  // particle is drawn (and then lands in the depth too, hidden behind the surface).
  RenderTarget& target = secondTarget(second);
  gl.BindFramebuffer(GL_FRAMEBUFFER, sphere_framebuffer_);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                          raw_depth->colorTexture(), 0);
  gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT1, GL_TEXTURE_2D,
                          target.colorTexture(), 0);
  const GLenum outputs[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1};
  gl.DrawBuffers(2, outputs);
  if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
    throw std::runtime_error("render target 'sphere depth + thickness' is incomplete");
  gl.Viewport(0, 0, raw_depth->width(), raw_depth->height());
  gl.Disable(GL_SCISSOR_TEST);
  gl.ClearBufferfv(GL_COLOR, 0, kClearDepth);
  gl.ClearBufferfv(GL_COLOR, 1, kClearZero);
  gl.Enable(GL_BLEND);
  gl.BlendFunc(GL_ONE, GL_ONE);
  gl.BlendEquationi(0, GL_MIN);
  gl.BlendEquationi(1, secondEquation(second));
  setSphereUniforms(projection, radius, second);
  drawSpheres(secondCount(second));
  gl.Disable(GL_BLEND);
}

void RenderContext::resolveThicknessFromDepths() {
  beginScreenPass(*thickness);
  thickness_program_.use();
  raw_depth->bindColorTexture(kUnitInput);
  far_depth->bindColorTexture(kUnitSecondInput);
  drawFullscreen();
}

}  // namespace pbf
