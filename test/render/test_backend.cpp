// Both GL backends create a context and render; the API renders only what is asked for,
// culls what is out of view, and fails loudly with errors that say what went wrong.

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <string>

#include "RenderTestSupport.h"

namespace {

pbf::RenderCamera smallCamera() {
  pbf::RenderCamera camera;
  camera.width = 160;
  camera.height = 120;
  camera.camera_to_world =
      pbf::lookAt(Eigen::Vector3f(0.6f, -0.6f, 0.6f), Eigen::Vector3f(0.0f, 0.0f, 0.2f));
  return camera;
}

std::vector<Eigen::Vector3f> smallBall() {
  return pbf_test::latticeBall(Eigen::Vector3f(0.0f, 0.0f, 0.2f), 0.1f, 0.02f);
}

std::size_t countFinite(const std::vector<float>& values) {
  std::size_t n = 0;
  for (float v : values) n += std::isfinite(v) ? 1 : 0;
  return n;
}

void expectRendersTheBall(pbf::FluidRenderer& renderer, const std::string& name) {
  pbf::RenderOutput out;
  renderer.render(smallBall(), 0.01f, smallCamera(), pbf_test::everything(), out);
  pbf_test::saveImages("backend_" + name, out);
  ASSERT_TRUE(out.rendered);
  EXPECT_EQ(out.rgba.size(), 160u * 120u * 4u);
  const std::size_t fluid = countFinite(out.depth);
  std::printf("%s: %s, %zu fluid pixels, %.1f ms\n", name.c_str(),
              renderer.glDescription().c_str(), fluid, out.timings.total);
  EXPECT_GT(fluid, 200u);
  EXPECT_LT(fluid, out.depth.size());
  for (float n : out.normals) ASSERT_TRUE(std::isfinite(n));
  for (float t : out.thickness) ASSERT_TRUE(std::isfinite(t));
}

TEST(GlBackend, OsMesaCreatesACoreContextAndRenders) {
  auto backend = pbf::createGlBackend("osmesa");
  EXPECT_EQ(backend->name(), "osmesa");
  EXPECT_NE(backend->getProcAddress("glDrawArrays"), nullptr);
  pbf::FluidRenderer renderer(std::move(backend), pbf_test::shaderDir());
  EXPECT_NE(renderer.glDescription().find("Core"), std::string::npos);
  expectRendersTheBall(renderer, "osmesa");
}

TEST(GlBackend, EglSurfacelessCreatesAContextAndRenders) {
  std::unique_ptr<pbf::GlBackend> backend;
  try {
    backend = pbf::createGlBackend("egl");
  } catch (const std::runtime_error& e) {
    // Only a platform without EGL_MESA_platform_surfaceless may skip; anything else fails.
    const std::string what = e.what();
    if (what.find("not available") != std::string::npos) GTEST_SKIP() << what;
    FAIL() << what;
  }
  EXPECT_EQ(backend->name(), "egl");
  pbf::FluidRenderer renderer(std::move(backend), pbf_test::shaderDir());
  expectRendersTheBall(renderer, "egl");
}

TEST(GlBackend, UnknownNameIsRejectedWithTheChoices) {
  try {
    pbf::createGlBackend("vulkan");
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("vulkan"), std::string::npos);
    EXPECT_NE(what.find("osmesa"), std::string::npos);
    EXPECT_NE(what.find("egl"), std::string::npos);
  }
}

TEST(FluidRenderer, MissingShaderDirectoryNamesTheFile) {
  try {
    pbf::FluidRenderer renderer(pbf::createGlBackend("osmesa"), "/nonexistent/shaders");
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/shaders/"), std::string::npos)
        << e.what();
  }
}

class RendererApi : public ::testing::Test {
 protected:
  RendererApi() : renderer_(pbf::createGlBackend("osmesa"), pbf_test::shaderDir()) {}
  pbf::FluidRenderer renderer_;
};

TEST_F(RendererApi, EmptyRequestDoesNoWork) {
  pbf::RenderOutput out;
  out.rgba.assign(10, 1);  // stale contents must not survive
  renderer_.render(smallBall(), 0.01f, smallCamera(),
                   pbf::RenderRequest{false, false, false, false}, out);
  EXPECT_FALSE(out.rendered);
  EXPECT_TRUE(out.rgba.empty());
  EXPECT_TRUE(out.depth.empty());
  EXPECT_EQ(out.timings.total, 0.0);
}

TEST_F(RendererApi, DepthOnlyRequestSkipsShading) {
  pbf::RenderOutput out;
  pbf::RenderRequest request{false, true, false, false};
  renderer_.render(smallBall(), 0.01f, smallCamera(), request, out);
  EXPECT_TRUE(out.rendered);
  EXPECT_TRUE(out.rgba.empty());
  EXPECT_EQ(out.depth.size(), 160u * 120u);
  EXPECT_EQ(out.timings.thickness, 0.0);
  EXPECT_EQ(out.timings.composite, 0.0);
  EXPECT_EQ(out.timings.normals, 0.0);
  EXPECT_GT(out.timings.filter, 0.0);
}

TEST_F(RendererApi, BackgroundIsNaNInDepthAndOpaqueInTheImage) {
  pbf::RenderOutput out;
  renderer_.render(smallBall(), 0.01f, smallCamera(), pbf_test::everything(), out);
  EXPECT_TRUE(std::isnan(out.depth.front()));  // a corner: no fluid
  EXPECT_EQ(out.rgba[3], 255);
  for (float d : out.depth) ASSERT_TRUE(std::isnan(d) || d > 0.0f);

  pbf::RenderOptions transparent;
  transparent.draw_background = false;
  renderer_.setOptions(transparent);
  renderer_.render(smallBall(), 0.01f, smallCamera(), pbf_test::everything(), out);
  EXPECT_EQ(out.rgba[3], 0);
}

TEST_F(RendererApi, ParticlesOutsideTheViewAreCulled) {
  std::vector<Eigen::Vector3f> particles = smallBall();
  const std::size_t in_view = particles.size();
  particles.emplace_back(5.0f, -5.0f, 5.0f);    // behind the camera
  particles.emplace_back(-3.0f, 3.0f, -20.0f);  // far below the view
  particles.emplace_back(0.0f, 0.0f, 20.0f);    // far above the view
  particles.emplace_back(std::nanf(""), 0.0f, 0.2f);  // diverged: never drawn
  pbf::RenderOutput out;
  renderer_.render(particles, 0.01f, smallCamera(), pbf_test::everything(), out);
  EXPECT_EQ(out.particles_in_view, in_view);
}

// Culling is conservative: a sphere whose centre is outside the image but whose body
// reaches into it is drawn.
TEST_F(RendererApi, SpheresReachingInFromOutsideTheImageAreDrawn) {
  const pbf::RenderCamera camera = smallCamera();
  const pbf::PinholeIntrinsics k = pbf::intrinsicsOf(camera);
  const float depth = 1.0f, radius = 0.05f;  // about 7 pixels in radius
  // Centre 3 pixels beyond the left edge, level with the image centre.
  const Eigen::Vector3f centre_camera(static_cast<float>((-3.0 - k.cx) / k.fx) * depth, 0.0f,
                                      depth);
  const Eigen::Vector3f centre = camera.camera_to_world * centre_camera;
  pbf::RenderOutput out;
  renderer_.render({centre}, radius, camera, pbf::RenderRequest{false, true, false, false}, out);
  EXPECT_EQ(out.particles_in_view, 1u);
  const float* row = &out.depth[static_cast<std::size_t>(camera.height / 2) * camera.width];
  EXPECT_TRUE(std::isfinite(row[0]));
  EXPECT_TRUE(std::isfinite(row[2]));
  EXPECT_FALSE(std::isfinite(row[12]));
}

TEST_F(RendererApi, PassTimingsAddUpToTheFrame) {
  pbf::RenderOutput out;
  renderer_.render(smallBall(), 0.01f, smallCamera(), pbf_test::everything(), out);
  const pbf::RenderTimings& t = out.timings;
  const double sum = t.cull_upload + t.depth + t.thickness + t.filter + t.normals +
                     t.composite + t.readback;
  for (double ms : {t.cull_upload, t.depth, t.thickness, t.filter, t.normals, t.composite,
                    t.readback})
    EXPECT_GE(ms, 0.0);
  EXPECT_GT(t.depth, 0.0);
  EXPECT_GT(t.composite, 0.0);
  EXPECT_LE(sum, t.total + 1e-6);
  EXPECT_GT(sum, 0.9 * t.total);
}

TEST_F(RendererApi, SurfaceOnlyDrawsFewerParticlesInTheDepthPass) {
  const std::vector<Eigen::Vector3f> particles = smallBall();
  // Neighbour counts within 1.5 spacings: interior lattice points have 18.
  std::vector<std::uint32_t> counts(particles.size(), 0);
  for (std::size_t i = 0; i < particles.size(); ++i)
    for (std::size_t j = 0; j < particles.size(); ++j)
      if (i != j && (particles[i] - particles[j]).norm() < 0.03f) ++counts[i];
  pbf::RenderOptions options;
  options.surface_particles_only = true;
  options.interior_neighbor_count = 18;
  renderer_.setOptions(options);

  // A depth-only request: the depth pass then runs alone (with an image, GL 4 contexts draw
  // every particle once for depth and thickness together).
  const pbf::RenderRequest depth_only{false, true, false, false};
  pbf::RenderOutput all, surface;
  pbf::RenderOptions every_particle;
  every_particle.surface_particles_only = false;
  renderer_.render(particles, 0.01f, smallCamera(), depth_only, surface, &counts);
  renderer_.setOptions(every_particle);
  renderer_.render(particles, 0.01f, smallCamera(), depth_only, all, &counts);
  std::printf("depth pass: %zu of %zu particles when surface only\n",
              surface.particles_in_depth, surface.particles_in_view);
  const std::size_t all_surface_count = surface.particles_in_depth;
  EXPECT_LT(surface.particles_in_depth, all.particles_in_depth * 7 / 10);
  EXPECT_EQ(surface.particles_in_view, all.particles_in_view);
  // Interior particles are mostly hidden: the depth image hardly changes (they show only
  // through the gaps between surface particles, which are closed before smoothing).
  std::size_t differing = 0, fluid = 0;
  for (std::size_t i = 0; i < all.depth.size(); ++i) {
    const bool a = std::isfinite(all.depth[i]), b = std::isfinite(surface.depth[i]);
    fluid += a ? 1 : 0;
    if (a != b || (a && std::abs(all.depth[i] - surface.depth[i]) > 0.2f * 0.01f)) ++differing;
  }
  EXPECT_LT(differing, fluid / 50);

  // With an image, thickness comes from the surface's front and back faces instead of
  // every chord; in pi/6 units it must tell the same story (mean within 35 %).
  renderer_.setOptions(options);
  renderer_.render(particles, 0.01f, smallCamera(), pbf_test::everything(), surface, &counts);
  renderer_.setOptions(every_particle);
  renderer_.render(particles, 0.01f, smallCamera(), pbf_test::everything(), all, &counts);
  EXPECT_EQ(surface.particles_in_depth, all_surface_count);
  double sum_all = 0, sum_surface = 0;
  for (std::size_t i = 0; i < all.thickness.size(); ++i) {
    sum_all += all.thickness[i];
    sum_surface += surface.thickness[i];
  }
  std::printf("mean thickness: every chord %.4f m, surface faces %.4f m\n",
              sum_all / all.thickness.size(), sum_surface / surface.thickness.size());
  EXPECT_NEAR(sum_surface / sum_all, 1.0, 0.35);

  std::vector<std::uint32_t> wrong_size(3, 0);
  renderer_.setOptions(options);
  EXPECT_THROW(renderer_.render(particles, 0.01f, smallCamera(), depth_only, surface,
                                &wrong_size),
               std::invalid_argument);
}

TEST_F(RendererApi, BadArgumentsAreRejected) {
  pbf::RenderOutput out;
  EXPECT_THROW(renderer_.render(smallBall(), 0.0f, smallCamera(), pbf::RenderRequest{}, out),
               std::invalid_argument);
  pbf::RenderCamera camera = smallCamera();
  camera.width = 0;
  EXPECT_THROW(renderer_.render(smallBall(), 0.01f, camera, pbf::RenderRequest{}, out),
               std::invalid_argument);
}

TEST_F(RendererApi, NoParticlesGiveAnEmptyScene) {
  pbf::RenderOutput out;
  renderer_.render({}, 0.01f, smallCamera(), pbf_test::everything(), out);
  EXPECT_TRUE(out.rendered);
  EXPECT_EQ(countFinite(out.depth), 0u);
}

}  // namespace
