// Sources and drains (issue 12, part 4): particles added and removed between steps keep the
// solver consistent, keep the ids of the others, start at rest density without a burst,
// never overlap fluid or solids, never exceed max_particles, and the books balance to the
// particle (emitted - drained = change of the particle count).

#include <gtest/gtest.h>

#include <cmath>
#include <set>
#include <unordered_map>

#include "SolverTestUtil.h"
#include "pbf_ros/core/FluidSources.h"

namespace {

// A 0.3 x 0.3 x 0.4 m tank with a 6 cm pool, d = 0.02, shipped solver defaults.
const char* kTank = R"(
container: {min: [0, 0, 0], max: [0.3, 0.3, 0.4]}
fluid:
  - box: {min: [0, 0, 0], max: [0.3, 0.3, 0.06]}
solver: {particle_spacing: 0.02}
)";

pbf::Scene tankScene(const std::string& extra = "") {
  return pbf::loadSceneString(std::string(kTank) + extra, "tank.yaml");
}

std::unordered_map<std::uint32_t, Eigen::Vector3f> byId(const pbf::PbfSolver& s) {
  std::unordered_map<std::uint32_t, Eigen::Vector3f> m;
  for (std::size_t k = 0; k < s.size(); ++k) m[s.ids()[k]] = s.positions()[k];
  return m;
}

float minDistance(const std::vector<Eigen::Vector3f>& a, const std::vector<Eigen::Vector3f>& b) {
  float best = 1e30f;
  for (const auto& p : a)
    for (const auto& q : b) best = std::min(best, (p - q).norm());
  return best;
}

TEST(ParticleChanges, AddAndRemoveKeepTheOthersAndTheirIds) {
  auto solver = pbf_test::makeSolver(tankScene());
  for (int s = 0; s < 5; ++s) solver->step();
  const std::size_t n0 = solver->size();
  const auto before = byId(*solver);
  const std::uint32_t first = solver->addParticles({{0.15f, 0.15f, 0.3f}, {0.17f, 0.15f, 0.3f}},
                                                   {{0, 0, 0}, {0, 0, -1}});
  EXPECT_EQ(first, n0);  // ids 0..n0-1 were given at the start
  EXPECT_EQ(solver->size(), n0 + 2);
  EXPECT_EQ(solver->densities().size(), n0 + 2);
  EXPECT_EQ(solver->neighborCounts().size(), n0 + 2);
  // Non-finite input or a size mismatch changes nothing.
  EXPECT_THROW(solver->addParticles({{NAN, 0, 0}}, {{0, 0, 0}}), std::invalid_argument);
  EXPECT_THROW(solver->addParticles({{0.1f, 0.1f, 0.1f}}, {}), std::invalid_argument);
  EXPECT_EQ(solver->size(), n0 + 2);
  EXPECT_EQ(solver->nextId(), n0 + 2);

  // Remove every particle whose id is a multiple of 3: the others keep id and position.
  std::vector<std::uint8_t> remove(solver->size());
  std::size_t expected = 0;
  for (std::size_t k = 0; k < solver->size(); ++k) expected += (remove[k] = solver->ids()[k] % 3 == 0);
  EXPECT_EQ(solver->removeParticles(remove), expected);
  EXPECT_EQ(solver->size(), n0 + 2 - expected);
  for (const auto& [id, x] : byId(*solver)) {
    EXPECT_NE(id % 3, 0u);
    if (id < n0) {
      EXPECT_EQ(x, before.at(id));
    }
  }
  EXPECT_THROW(solver->removeParticles(std::vector<std::uint8_t>(3, 0)), std::invalid_argument);
  // The solver steps on with the changed set, finite, and gives no id twice.
  for (int s = 0; s < 20; ++s) ASSERT_FALSE(solver->step().failed);
  for (const auto& x : solver->positions()) ASSERT_TRUE(x.allFinite());
  const std::uint32_t again = solver->addParticles({{0.1f, 0.1f, 0.3f}}, {{0, 0, 0}});
  EXPECT_EQ(again, n0 + 2);
  std::set<std::uint32_t> ids(solver->ids().begin(), solver->ids().end());
  EXPECT_EQ(ids.size(), solver->size());
}

TEST(FluidSources, EmittedBlockStartsAtRestDensityWithoutABurst) {
  pbf::Scene scene = tankScene();
  auto solver = pbf_test::makeSolver(scene);
  pbf::FluidSources sources({}, {}, solver->size());
  pbf::FluidBlock block;  // 10 x 10 x 10 cm of water well above the pool, at rest
  block.min = Eigen::Vector3f(0.1f, 0.1f, 0.2f);
  block.max = Eigen::Vector3f(0.2f, 0.2f, 0.3f);
  const std::size_t n0 = solver->size();
  const pbf::SiteCount c = sources.emitBlock(*solver, block, Eigen::Isometry3f::Identity(), 100000);
  EXPECT_EQ(c.added, 125u);
  EXPECT_EQ(solver->size(), n0 + 125);
  const float g = 9.81f;
  double t = 0.0;
  for (int s = 0; s < 10; ++s) {
    const pbf::StepStats st = solver->step();
    t += st.dt;
    // Free fall and nothing more: the block's lattice is at rest density (no burst), and
    // the resting pool below is untouched in these steps.
    EXPECT_LE(st.max_speed, g * t + 3.0 * g * st.dt) << "step " << s;
    if (s == 0) {
      EXPECT_LT(st.max_density_error, 0.01);
    }
  }
}

TEST(FluidSources, JetFromANozzleRisesNoFasterThanItsSpeedAndGravity) {
  pbf::Scene scene = tankScene(R"(
emitters:
  - {position: [0.15, 0.15, 0.3], direction: [0, 0, -1], radius: 0.03, speed: 0.8}
)");
  auto solver = pbf_test::makeSolver(scene);
  pbf::FluidSources sources(scene.emitters, scene.drains, solver->size());
  const float g = 9.81f;
  double t = 0.0;
  std::size_t layers = 0;
  for (int s = 0; s < 40; ++s) {
    const pbf::StepStats st = solver->step();
    t += st.dt;
    EXPECT_LE(st.max_speed, 0.8 + g * t + 3.0 * g * st.dt) << "step " << s;
    layers += sources.afterStep(*solver, st.dt, 100000).emitted > 0;
  }
  // At d = 0.02 a 3 cm nozzle holds 9 sites (|i|, |j| <= 1); a layer every d / v = 25 ms.
  const std::size_t per_layer = 9;
  EXPECT_EQ(sources.emitted() % per_layer, 0u);
  EXPECT_NEAR(double(sources.emitted()) / per_layer, std::floor(0.8 * t / 0.02), 1.0);
  EXPECT_EQ(solver->size(), sources.initialParticles() + sources.emitted());
}

TEST(FluidSources, NewParticlesNeverOverlapFluidOrSolids) {
  pbf::Scene scene = tankScene(R"(
obstacles:
  - {sphere: {center: [0.15, 0.15, 0.15], radius: 0.05}}
)");
  auto solver = pbf_test::makeSolver(scene);
  const std::vector<Eigen::Vector3f> old = solver->positions();
  pbf::FluidSources sources({}, {}, solver->size());
  pbf::FluidBlock block;  // overlaps the pool (z < 0.06) and the sphere
  block.min = Eigen::Vector3f(0.0f, 0.0f, 0.0f);
  block.max = Eigen::Vector3f(0.3f, 0.3f, 0.2f);
  const pbf::SiteCount c = sources.emitBlock(*solver, block, Eigen::Isometry3f::Identity(), 100000);
  EXPECT_EQ(c.occupied, 15u * 15u * 3u);  // the pool's three layers
  EXPECT_GT(c.in_solid, 0u);
  EXPECT_GT(c.added, 0u);
  const std::vector<Eigen::Vector3f> all = solver->positions();
  const std::vector<Eigen::Vector3f> fresh(all.end() - c.added, all.end());
  EXPECT_GE(minDistance(fresh, old), pbf::kSiteClearance * 0.02f);
  for (const auto& p : fresh) {
    Eigen::Vector3f n;
    EXPECT_GE(solver->obstacles()[0].signedDistance(p, n), 0.01f - 1e-6f);
  }
  // The same block again: everything is taken, nothing is added, the refusal says why.
  try {
    sources.emitBlock(*solver, block, Eigen::Isometry3f::Identity(), 100000);
    FAIL() << "a full block was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("no free lattice site"), std::string::npos) << e.what();
  }
  EXPECT_EQ(solver->size(), all.size());
}

TEST(FluidSources, MaxParticlesIsNeverExceededAndARefusalLosesNothing) {
  pbf::Scene scene = tankScene(R"(
emitters:
  - {position: [0.15, 0.15, 0.3], direction: [0, 0, -1], radius: 0.03, speed: 1.0}
)");
  auto solver = pbf_test::makeSolver(scene);
  const std::size_t n0 = solver->size();
  const std::size_t limit = n0 + 20;  // room for two layers of 9
  pbf::FluidSources sources(scene.emitters, scene.drains, n0);
  pbf::FluidBlock block;
  block.min = Eigen::Vector3f(0.1f, 0.1f, 0.2f);
  block.max = Eigen::Vector3f(0.2f, 0.2f, 0.3f);
  try {
    sources.emitBlock(*solver, block, Eigen::Isometry3f::Identity(), limit);
    FAIL() << "a block beyond max_particles was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_particles (" + std::to_string(limit) + ")"), std::string::npos)
        << e.what();
  }
  EXPECT_EQ(solver->size(), n0);
  bool held = false;
  for (int s = 0; s < 60; ++s) {
    const pbf::StepStats st = solver->step();
    const auto r = sources.afterStep(*solver, st.dt, limit);
    held = held || !r.held_by_limit.empty();
    ASSERT_LE(solver->size(), limit);
    ASSERT_EQ(solver->size(), n0 + sources.emitted());
  }
  EXPECT_TRUE(held);
  EXPECT_EQ(sources.emitted(), 18u);
}

TEST(FluidSources, EmittedMinusDrainedIsTheChangeOfTheFluidToTheParticle) {
  // A tap (9 sites a layer, 0.0036 m^3/s = 1 m/s) pours a fixed volume into the tank; drains
  // in two bottom corners take water out.
  pbf::Scene scene = tankScene(R"(
emitters:
  - {position: [0.15, 0.15, 0.3], direction: [0, 0, -1], radius: 0.03, rate: 0.0036, volume: 0.0012}
drains:
  - {box: {min: [0.0, 0.0, 0.0], max: [0.06, 0.06, 0.03]}}
  - {sphere: {center: [0.3, 0.3, 0.0], radius: 0.05}}
)");
  auto solver = pbf_test::makeSolver(scene);
  pbf::FluidSources sources(scene.emitters, scene.drains, solver->size());
  std::set<std::uint32_t> seen(solver->ids().begin(), solver->ids().end());
  std::uint64_t drained_total = 0;
  while (solver->time() < 0.8) {
    const std::uint32_t next = solver->nextId();
    const pbf::StepStats st = solver->step();
    ASSERT_FALSE(st.failed);
    const auto r = sources.afterStep(*solver, st.dt, 100000);
    drained_total += r.drained;
    ASSERT_EQ(solver->size(), sources.initialParticles() + sources.emitted() - sources.drained());
    for (std::size_t k = 0; k < solver->size(); ++k) {
      const std::uint32_t id = solver->ids()[k];
      if (id >= next) {
        ASSERT_TRUE(seen.insert(id).second) << "id " << id << " given twice";
      }
      for (const pbf::Drain& d : scene.drains) ASSERT_FALSE(d.contains(solver->positions()[k]));
    }
  }
  EXPECT_EQ(sources.drained(), drained_total);
  EXPECT_GT(sources.drained(), 0u);
  // The volume is whole particles: 0.0012 m^3 / d^3 = 150 particles, exactly.
  EXPECT_EQ(sources.emitted(), 150u);
  EXPECT_EQ(sources.emittedBy(0), 150u);
  const double mass = solver->params().particleMass();
  EXPECT_DOUBLE_EQ(mass * double(solver->size()) - mass * double(sources.initialParticles()),
                   mass * (double(sources.emitted()) - double(sources.drained())));
}

TEST(FluidSources, AnEmitterInAFrameWaitsForItsPoseAndFollowsIt) {
  pbf::Scene scene = tankScene(R"(
emitters:
  - {frame: tap, position: [0, 0, 0], direction: [0, 0, -1], radius: 0.01, speed: 1.0}
)");
  auto solver = pbf_test::makeSolver(scene);
  pbf::FluidSources sources(scene.emitters, scene.drains, solver->size());
  for (int s = 0; s < 20; ++s) sources.afterStep(*solver, solver->step().dt, 100000);
  EXPECT_EQ(sources.emitted(), 0u);  // tf has not told where 'tap' is: nothing at the origin
  // The frame turned on its side at (0.15, 0.15, 0.3): the jet goes along -z of the frame,
  // i.e. +x of the fluid frame.
  const Eigen::Isometry3f tap = Eigen::Translation3f(0.15f, 0.15f, 0.3f) *
                                Eigen::AngleAxisf(-float(M_PI) / 2, Eigen::Vector3f::UnitY());
  EXPECT_THROW(sources.setEmitterPose(0, Eigen::Isometry3f(Eigen::Matrix4f::Constant(NAN))), std::invalid_argument);
  sources.setEmitterPose(0, tap);
  const std::size_t before = solver->size();
  while (sources.emitted() == 0) sources.afterStep(*solver, solver->step().dt, 100000);
  ASSERT_EQ(sources.emitted(), 1u);  // a 1 cm nozzle at d = 0.02: a single file
  const Eigen::Vector3f p = solver->positions()[before];
  const Eigen::Vector3f v = solver->velocities()[before];
  EXPECT_NEAR(p.y(), 0.15f, 1e-5f);
  EXPECT_NEAR(p.z(), 0.3f, 1e-5f);
  EXPECT_GE(p.x(), 0.15f - 1e-5f);
  EXPECT_TRUE(v.isApprox(Eigen::Vector3f(1.0f, 0.0f, 0.0f), 1e-5f)) << v.transpose();
}

// A nozzle far wider than the tank places only the sites that can land in it (its disc is
// clipped to the container's reach before the sites are placed), and every one of those:
// near a corner of the tank, 1.5 m wide, pointing down, its first layer fills each of the
// 15 x 15 lattice columns of the 0.3 x 0.3 m section.
TEST(FluidSources, ANozzleWiderThanTheTankFillsEveryColumnOfIt) {
  pbf::Scene scene = tankScene(R"(
emitters:
  - {position: [0.05, 0.05, 0.3], direction: [0, 0, -1], radius: 1.5, speed: 1.0}
)");
  auto solver = pbf_test::makeSolver(scene);
  pbf::FluidSources sources(scene.emitters, scene.drains, solver->size());
  const std::size_t before = solver->size();
  while (sources.emitted() == 0) sources.afterStep(*solver, solver->step().dt, 100000);
  std::set<std::pair<int, int>> columns;
  for (std::size_t k = before; k < solver->size(); ++k) {
    const Eigen::Vector3f p = solver->positions()[k];
    columns.insert({static_cast<int>(std::lround((p.x() - 0.01f) / 0.02f)),
                    static_cast<int>(std::lround((p.y() - 0.01f) / 0.02f))});
  }
  EXPECT_EQ(columns.size(), 225u);
  EXPECT_EQ(sources.emitted() % 225, 0u) << sources.emitted();
}

TEST(FluidSources, BadEmittersDrainsAndBlocksAreNamed) {
  auto expectError = [](const std::string& yaml, const std::string& key) {
    try {
      pbf::loadSceneString(std::string(kTank) + yaml, "bad.yaml");
      ADD_FAILURE() << "accepted: " << yaml;
    } catch (const pbf::SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  const std::string nozzle = "emitters:\n  - {position: [0.1, 0.1, 0.2], direction: [0, 0, -1], ";
  expectError(nozzle + "radius: 0, speed: 1}\n", "'emitters[0].radius'");
  expectError(nozzle + "radius: 0.02, speed: .nan}\n", "'emitters[0].speed'");
  expectError(nozzle + "radius: 0.02, rate: -1}\n", "'emitters[0].rate'");
  expectError(nozzle + "radius: 0.02}\n", "'emitters[0]'");
  expectError(nozzle + "radius: 0.02, speed: 1, rate: 0.001}\n", "not both");
  expectError(nozzle + "radius: 0.02, speed: 1, volume: -2}\n", "'emitters[0].volume'");
  expectError(nozzle + "radius: 0.02, speed: 1, nozzle: 3}\n", "emitters[0].nozzle");
  expectError("emitters:\n  - {position: [0.1, 0.1, 0.2], direction: [0, 0, 0], radius: 0.02, speed: 1}\n",
              "'emitters[0].direction'");
  expectError("emitters:\n  - {position: [5, 0.1, 0.2], direction: [0, 0, -1], radius: 0.02, speed: 1}\n",
              "emitters[0].position is outside the container");
  expectError(nozzle + "radius: 0.02, speed: 3.0e8}\n", "'emitters[0].speed': expected at most 1000 m/s");
  // No jet faster than the fluid's speed cap (4 x sqrt(2 g 0.4 m) = 11.2 m/s here), given as
  // a speed or as a rate (5 sites of d^2: 1 m^3/s is 500 m/s); it was capped in silence.
  expectError(nozzle + "radius: 0.02, speed: 50}\n", "emitters[0]: 50 m/s is faster than the fluid's speed cap, 11.2");
  expectError(nozzle + "radius: 0.02, rate: 1}\n", "emitters[0]: 500 m/s (rate 1 m^3/s at particle_spacing 0.02 m)");
  expectError(nozzle + "radius: 1.0e30, speed: 1}\n", "emitters[0].radius 1e+30 m is more than 200 particle spacings");
  expectError("drains:\n  - {box: {min: [0.1, 0, 0], max: [0.0, 0.1, 0.1]}}\n", "'drains[0].box'");
  expectError("drains:\n  - {sphere: {center: [0.1, 0, 0], radius: inf}}\n", "'drains[0].sphere.radius'");
  expectError("drains:\n  - {}\n", "'drains[0]'");

  pbf::Emitter e;
  e.speed = 1.0f;
  e.radius = 0.0f;
  EXPECT_EQ(e.validate().rfind("radius", 0), 0u) << e.validate();
  e.radius = 0.02f;
  e.position.x() = INFINITY;
  EXPECT_EQ(e.validate().rfind("position", 0), 0u) << e.validate();
  e.position.x() = 0.0f;
  e.speed = 0.0f;
  e.rate = -1.0f;
  EXPECT_EQ(e.validate().rfind("rate", 0), 0u) << e.validate();
  EXPECT_THROW(pbf::FluidSources({e}, {}, 0), std::invalid_argument);

  pbf::FluidBlock b;
  b.min = Eigen::Vector3f(0.1f, 0.1f, NAN);
  b.max = Eigen::Vector3f(0.2f, 0.2f, 0.2f);
  EXPECT_EQ(pbf::validateBlock(b).rfind("min", 0), 0u);
  b.min.z() = 0.3f;
  EXPECT_EQ(pbf::validateBlock(b).rfind("min/max", 0), 0u);
  b.min.z() = 0.1f;
  b.velocity = Eigen::Vector3f(0.0f, 0.0f, -2000.0f);
  EXPECT_EQ(pbf::validateBlock(b).rfind("velocity: expected at most 1000 m/s", 0), 0u) << pbf::validateBlock(b);
  b.velocity.setZero();
  b.shape = pbf::FluidBlock::Shape::Sphere;
  b.radius = -1.0f;
  EXPECT_EQ(pbf::validateBlock(b).rfind("radius", 0), 0u);
  // A bad block is refused by emitBlock and the solver is untouched.
  auto solver = pbf_test::makeSolver(tankScene());
  pbf::FluidSources sources({}, {}, solver->size());
  const std::size_t n0 = solver->size();
  EXPECT_THROW(sources.emitBlock(*solver, b, Eigen::Isometry3f::Identity(), 100000), std::invalid_argument);
  EXPECT_EQ(solver->size(), n0);
  EXPECT_EQ(sources.emitted(), 0u);
  // A block too large to count its sites says so (it read "about inf lattice sites").
  b = pbf::FluidBlock();
  b.min = Eigen::Vector3f::Constant(-3e38f);
  b.max = Eigen::Vector3f::Constant(3e38f);
  try {
    sources.emitBlock(*solver, b, Eigen::Isometry3f::Identity(), 100000);
    ADD_FAILURE() << "a block of 6e38 m was accepted";
  } catch (const std::invalid_argument& x) {
    EXPECT_NE(std::string(x.what()).find("more lattice sites than can be counted"), std::string::npos) << x.what();
  }
  EXPECT_EQ(solver->size(), n0);

  // A direction whose plain norm overflows a float is still a direction: it was refused as
  // "got [0, 0, 0]", the overflowed normalisation rather than what the user wrote.
  const pbf::Scene far = pbf::loadSceneString(std::string(kTank) +
                                                  "emitters:\n  - {position: [0.1, 0.1, 0.2], direction: [1.0e38, "
                                                  "1.0e38, 0], radius: 0.02, speed: 1}\n",
                                              "far.yaml");
  ASSERT_EQ(far.emitters.size(), 1u);
  EXPECT_TRUE(far.emitters[0].direction.isApprox(Eigen::Vector3f(1.0f, 1.0f, 0.0f).normalized()))
      << far.emitters[0].direction.transpose();
}

// A jet faster than 8 spacings per step (a fixed step, or the first one): the layers that
// left the nozzle first are dropped and the newest 8 kept, so the jet starts at its nozzle.
// Keeping the farthest put a 1000 m/s jet's layers metres ahead, outside the container, at
// every step, and it never emitted (a helper probe).
TEST(FluidSources, AJetTooFastForTheStepStartsAtItsNozzle) {
  pbf::Scene scene = tankScene();
  scene.solver.adaptive_time_step = false;
  scene.solver.time_step = 1.0f / 60.0f;
  auto solver = pbf_test::makeSolver(scene);
  pbf::Emitter e;
  e.position = Eigen::Vector3f(0.15f, 0.15f, 0.3f);
  e.direction = Eigen::Vector3f(0.0f, 0.0f, -1.0f);
  e.radius = 0.01f;  // one site per layer
  e.speed = 12.0f;   // 0.2 m = 10 spacings per step of 1/60 s
  pbf::FluidSources sources({e}, {}, solver->size());
  const std::size_t n0 = solver->size();
  const pbf::StepStats st = solver->step();
  const pbf::FluidSources::StepResult r = sources.afterStep(*solver, st.dt, 100000);
  ASSERT_EQ(r.too_fast, std::vector<std::size_t>{0});
  ASSERT_EQ(r.emitted, 8u);
  float nearest = 1.0f, farthest = 0.0f;
  for (std::size_t k = n0; k < solver->size(); ++k) {
    const float ahead = 0.3f - solver->positions()[k].z();
    nearest = std::min(nearest, ahead), farthest = std::max(farthest, ahead);
  }
  EXPECT_NEAR(nearest, 0.0f, 1e-5f);
  EXPECT_NEAR(farthest, 7 * 0.02f, 1e-5f);
}

}  // namespace
