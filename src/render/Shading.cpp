// Smoothed depth -> normals (normals.frag) -> the shaded image: the cached procedural
// background (background.frag) with the fluid composited over it (composite.frag).

#include "RenderContext.h"

namespace pbf {
namespace {

// Everything the cached background depends on.
std::vector<float> backgroundKey(const RenderCamera& c, const RenderOptions& o) {
  std::vector<float> key(c.camera_to_world.matrix().data(),
                         c.camera_to_world.matrix().data() + 16);
  key.insert(key.end(), {c.vertical_fov, static_cast<float>(c.width),
                         static_cast<float>(c.height), o.floor_height, o.floor_tile_size,
                         o.light_direction.x(), o.light_direction.y(), o.light_direction.z(),
                         o.draw_background ? 1.0f : 0.0f});
  return key;
}

}  // namespace

void RenderContext::computeNormals(const RenderTarget& surface_depth, float focal,
                                   const Eigen::Vector2f& principal) {
  beginScreenPass(*normals);
  normals_program_.use();
  gl.Uniform1f(normals_program_.uniform("focal_pixels"), focal);
  gl.Uniform2f(normals_program_.uniform("principal_point"), principal.x(), principal.y());
  surface_depth.bindColorTexture(kUnitInput);
  drawFullscreen();
}

// The uniforms of procedural_scene.glsl and of the camera rays.
void RenderContext::setSceneUniforms(const ShaderProgram& p, const RenderCamera& camera,
                                     const RenderOptions& o, float focal,
                                     const Eigen::Vector2f& principal) {
  const Eigen::Matrix3f world_from_view =
      glViewFromWorld(camera).topLeftCorner<3, 3>().transpose();
  const Eigen::Vector3f eye = camera.camera_to_world.translation();
  const Eigen::Vector3f light = o.light_direction.normalized();
  gl.Uniform1f(p.uniform("focal_pixels"), focal);
  gl.Uniform2f(p.uniform("principal_point"), principal.x(), principal.y());
  gl.UniformMatrix3fv(p.uniform("world_from_view"), 1, GL_FALSE, world_from_view.data());
  gl.Uniform3f(p.uniform("eye_world"), eye.x(), eye.y(), eye.z());
  gl.Uniform3f(p.uniform("light_direction"), light.x(), light.y(), light.z());
  gl.Uniform1f(p.uniform("floor_height"), o.floor_height);
  gl.Uniform1f(p.uniform("floor_tile_size"), o.floor_tile_size);
}

void RenderContext::updateBackground(const RenderCamera& camera, const RenderOptions& o,
                                     float focal, const Eigen::Vector2f& principal) {
  std::vector<float> key = backgroundKey(camera, o);
  if (key == background_key_) return;  // unchanged camera and scene: keep the cached one
  background->bindForDrawing();
  gl.Disable(GL_SCISSOR_TEST);
  background_program_.use();
  setSceneUniforms(background_program_, camera, o, focal, principal);
  gl.Uniform1i(background_program_.uniform("draw_background"), o.draw_background ? 1 : 0);
  drawFullscreen();
  background_key_ = std::move(key);
}

void RenderContext::composite(const RenderTarget& surface_depth, const RenderCamera& camera,
                              const RenderOptions& o, float focal,
                              const Eigen::Vector2f& principal, float radius) {
  // The background everywhere (a copy), then the fluid shaded inside its rectangle.
  gl.BindFramebuffer(GL_READ_FRAMEBUFFER, background->framebuffer());
  gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, color->framebuffer());
  gl.Disable(GL_SCISSOR_TEST);
  gl.BlitFramebuffer(0, 0, camera.width, camera.height, 0, 0, camera.width, camera.height,
                     GL_COLOR_BUFFER_BIT, GL_NEAREST);
  color->bindForDrawing();
  limitToFluid();
  const ShaderProgram& p = composite_program_;
  p.use();
  setSceneUniforms(p, camera, o, focal, principal);
  gl.Uniform1f(p.uniform("refractive_index"), o.refractive_index);
  gl.Uniform1f(p.uniform("fresnel_f0"), o.fresnel_f0);
  gl.Uniform3f(p.uniform("absorption"), o.absorption.x(), o.absorption.y(), o.absorption.z());
  gl.Uniform1f(p.uniform("specular_strength"), o.specular_strength);
  gl.Uniform1f(p.uniform("specular_exponent"), o.specular_exponent);
  gl.Uniform1f(p.uniform("radius"), radius);
  surface_depth.bindColorTexture(kUnitInput);
  normals->bindColorTexture(kUnitSecondInput);
  thickness->bindColorTexture(kUnitThickness);
  thickness->generateMipmaps();
  background->bindColorTexture(kUnitBackground);
  drawFullscreen();
  gl.Disable(GL_SCISSOR_TEST);
}

}  // namespace pbf
