#include "pbf_ros/core/FluidSources.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace pbf {

namespace {

// At most this many layers per emitter and step: a jet faster than d per step (a fixed,
// coarse dt) emits them all, spaced d apart; beyond it the nozzle is choked, not piled up.
constexpr int kMaxLayersPerStep = 8;
// An emitBlock lattice larger than this many times max_particles is refused from its size
// alone, before any site is allocated.
constexpr double kSiteWalkFactor = 4.0;

bool finite(float x) { return std::isfinite(x); }

std::string describe(const Eigen::Vector3f& v) {
  std::ostringstream s;
  s.precision(9);  // a float whole: at 6 digits 0.1 and 0.1000001 printed alike
  s << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
  return s.str();
}

// Two unit vectors spanning the plane normal to n.
void planeBasis(const Eigen::Vector3f& n, Eigen::Vector3f& u, Eigen::Vector3f& w) {
  int least = 0;
  n.cwiseAbs().minCoeff(&least);
  u = n.cross(Eigen::Vector3f::Unit(least)).normalized();
  w = n.cross(u);
}

// Lattice offsets (i d, j d) within the nozzle's radius: the centre always, so a nozzle
// narrower than d still emits a single file.
std::vector<Eigen::Vector2f> discSites(float radius, float d) {
  std::vector<Eigen::Vector2f> sites;
  const int n = static_cast<int>(std::floor(radius / d));
  for (int j = -n; j <= n; ++j)
    for (int i = -n; i <= n; ++i) {
      const Eigen::Vector2f s(i * d, j * d);
      if (s.squaredNorm() <= radius * radius * (1.0f + 1e-5f)) sites.push_back(s);
    }
  return sites;
}

double blockLatticePoints(const FluidBlock& b, float d) {
  const Eigen::Vector3f size = b.shape == FluidBlock::Shape::Box ? Eigen::Vector3f(b.max - b.min)
                                                                 : Eigen::Vector3f::Constant(2.0f * b.radius);
  double n = 1.0;
  for (int a = 0; a < 3; ++a) n *= std::max(1.0, std::floor(static_cast<double>(size[a]) / d));
  return n;
}

std::int64_t cellKey(const Eigen::Vector3i& c) {
  // 21 bits per axis: the sites of one request span far fewer cells than 2^21.
  return (std::int64_t(c.x() & 0x1fffff) << 42) | (std::int64_t(c.y() & 0x1fffff) << 21) |
         std::int64_t(c.z() & 0x1fffff);
}

}  // namespace

namespace {
// Its speed, or its rate through `sites` lattice sites of d^2 each.
double speedThrough(const Emitter& e, std::size_t sites, float d) {
  return e.speed > 0.0f ? double(e.speed) : double(e.rate) / (double(sites) * d * d);
}
}  // namespace

double emitterSpeed(const Emitter& e, float d) {
  return speedThrough(e, discSites(e.radius, d).size(), d);
}

std::string Emitter::validate() const {
  std::ostringstream e;
  if (!position.allFinite()) return "position: expected 3 finite numbers, got " + describe(position);
  // stableNorm: a direction of [1e38, 1e38, 0] is fine, though its plain norm overflows.
  if (!direction.allFinite() || !(direction.stableNorm() > 1e-6f))
    return "direction: expected a finite, non-zero vector, got " + describe(direction);
  if (!finite(radius) || !(radius > 0.0f)) {
    e << "radius: expected a number > 0 [m], got " << radius;
    return e.str();
  }
  if (!finite(speed) || speed < 0.0f || !finite(rate) || rate < 0.0f) {
    e << (finite(speed) && speed >= 0.0f ? "rate" : "speed") << ": expected a finite number > 0, got "
      << (finite(speed) && speed >= 0.0f ? rate : speed);
    return e.str();
  }
  if ((speed > 0.0f) == (rate > 0.0f))
    return "speed/rate: expected exactly one of speed [m/s] or rate [m^3/s], > 0";
  if (speed > kMaxEmitterSpeed) {
    e << "speed: expected at most " << kMaxEmitterSpeed << " m/s, got " << speed;
    return e.str();
  }
  if (!finite(volume) || volume < 0.0f) {
    e << "volume: expected a number >= 0 [m^3] (0 = no limit), got " << volume;
    return e.str();
  }
  if (!finite(start) || start < 0.0f) {
    e << "start: expected a time >= 0 [s], got " << start;
    return e.str();
  }
  if (!pose.matrix().allFinite()) return "pose: not finite";
  return "";
}

std::string Drain::validate() const {
  std::ostringstream e;
  if (shape == Shape::Box) {
    if (!min.allFinite()) return "box.min: expected 3 finite numbers, got " + describe(min);
    if (!max.allFinite()) return "box.max: expected 3 finite numbers, got " + describe(max);
    if (!(min.array() < max.array()).all()) return "box: expected min < max on every axis";
    return "";
  }
  if (!center.allFinite()) return "sphere.center: expected 3 finite numbers, got " + describe(center);
  if (!finite(radius) || !(radius > 0.0f)) {
    e << "sphere.radius: expected a number > 0 [m], got " << radius;
    return e.str();
  }
  return "";
}

std::string validateBlock(const FluidBlock& b) {
  std::ostringstream e;
  if (!b.velocity.allFinite()) return "velocity: expected 3 finite numbers, got " + describe(b.velocity);
  if (b.velocity.norm() > kMaxEmitterSpeed) {
    e << "velocity: expected at most " << kMaxEmitterSpeed << " m/s, got " << describe(b.velocity);
    return e.str();
  }
  if (b.shape == FluidBlock::Shape::Box) {
    if (!b.min.allFinite()) return "min: expected 3 finite numbers, got " + describe(b.min);
    if (!b.max.allFinite()) return "max: expected 3 finite numbers, got " + describe(b.max);
    if (!(b.min.array() < b.max.array()).all())
      return "min/max: expected min < max on every axis, got min " + describe(b.min) + ", max " + describe(b.max);
    return "";
  }
  if (!b.center.allFinite()) return "center: expected 3 finite numbers, got " + describe(b.center);
  if (!finite(b.radius) || !(b.radius > 0.0f)) {
    e << "radius: expected a number > 0 [m], got " << b.radius;
    return e.str();
  }
  return "";
}

std::vector<Eigen::Vector3f> blockSites(const FluidBlock& b, float d) {
  std::vector<Eigen::Vector3f> sites;
  if (!validateBlock(b).empty() || !(d > 0.0f)) return sites;
  // The scene's lattice, but a size that is a whole number of spacings up to round-off
  // gets them all (an ~emit request's box is typed by hand).
  const auto [start, n] = blockLattice(b, d, 1e-3f);
  for (int z = 0; z < n.z(); ++z)
    for (int y = 0; y < n.y(); ++y)
      for (int x = 0; x < n.x(); ++x) {
        const Eigen::Vector3f p = start + d * Eigen::Vector3f(x, y, z);
        if (b.shape == FluidBlock::Shape::Sphere && (p - b.center).squaredNorm() > b.radius * b.radius) continue;
        sites.push_back(p);
      }
  return sites;
}

SiteCount keepFreeSites(const PbfSolver& solver, std::vector<Eigen::Vector3f>& sites) {
  SiteCount count;
  const float d = solver.params().particle_spacing;
  const float r = 0.5f * d;
  // A scene's lattice sits exactly d/2 from the walls; round-off must not push it out.
  const float wall_gap = r * (1.0f - 1e-4f);
  // Container and solids first: cheap per site.
  const Eigen::AlignedBox3f& box = solver.container();
  const Eigen::Isometry3f to_box = solver.containerPose().inverse(Eigen::Isometry);
  std::vector<Eigen::Vector3f> candidates;
  candidates.reserve(sites.size());
  for (const Eigen::Vector3f& p : sites) {
    if (!box.isEmpty()) {
      const Eigen::Vector3f q = to_box * p;
      if (((q.array() - box.min().array()) < wall_gap).any() ||
          ((box.max().array() - q.array()) < wall_gap).any()) {
        ++count.outside;
        continue;
      }
    }
    bool solid = false;
    for (const Obstacle& o : solver.obstacles()) {
      const float reach = o.boundingRadius() + r;
      if ((p - o.pose.translation()).squaredNorm() > reach * reach) continue;
      Eigen::Vector3f normal;
      if (o.signedDistance(p, normal) < r) {
        solid = true;
        break;
      }
    }
    if (solid) {
      ++count.in_solid;
      continue;
    }
    candidates.push_back(p);
  }
  // Then the fluid: hash the candidates by cell (size d) and let every existing particle
  // near them block the sites within the clearance. One pass over the particles.
  const float clear = kSiteClearance * d;
  std::vector<std::uint8_t> blocked(candidates.size(), 0);
  if (!candidates.empty() && solver.size() > 0) {
    Eigen::AlignedBox3f reach;
    std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      reach.extend(candidates[i]);
      const Eigen::Vector3i c = (candidates[i] / d).array().floor().cast<int>();
      cells[cellKey(c)].push_back(static_cast<std::uint32_t>(i));
    }
    reach.min().array() -= d;
    reach.max().array() += d;
    for (const Eigen::Vector3f& x : solver.positions()) {
      if (!reach.contains(x)) continue;
      const Eigen::Vector3i c = (x / d).array().floor().cast<int>();
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const auto it = cells.find(cellKey(c + Eigen::Vector3i(dx, dy, dz)));
            if (it == cells.end()) continue;
            for (std::uint32_t i : it->second)
              if ((candidates[i] - x).squaredNorm() < clear * clear) blocked[i] = 1;
          }
    }
  }
  sites.clear();
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (blocked[i])
      ++count.occupied;
    else
      sites.push_back(candidates[i]);
  }
  count.added = sites.size();
  return count;
}

FluidSources::FluidSources(std::vector<Emitter> emitters, std::vector<Drain> drains,
                           std::size_t initial_particles)
    : emitters_(std::move(emitters)), drains_(std::move(drains)), initial_particles_(initial_particles) {
  if (emitters_.size() > kMaxSceneEmitters || drains_.size() > kMaxSceneDrains)
    throw std::invalid_argument("at most " + std::to_string(kMaxSceneEmitters) + " emitters and " +
                                std::to_string(kMaxSceneDrains) + " drains");
  for (std::size_t k = 0; k < emitters_.size(); ++k) {
    const std::string err = emitters_[k].validate();
    if (!err.empty()) throw std::invalid_argument("emitters[" + std::to_string(k) + "]." + err);
    emitters_[k].direction.stableNormalize();
  }
  for (std::size_t k = 0; k < drains_.size(); ++k) {
    const std::string err = drains_[k].validate();
    if (!err.empty()) throw std::invalid_argument("drains[" + std::to_string(k) + "]." + err);
  }
  state_.resize(emitters_.size());
  for (std::size_t k = 0; k < emitters_.size(); ++k) state_[k].placed = emitters_[k].frame.empty();
}

void FluidSources::setEmitterPose(std::size_t k, const Eigen::Isometry3f& pose) {
  if (k >= emitters_.size())
    throw std::invalid_argument("emitter index " + std::to_string(k) + " out of range");
  if (!pose.matrix().allFinite()) throw std::invalid_argument("emitter pose must be finite");
  emitters_[k].pose = pose;
  state_[k].placed = true;
}

FluidSources::StepResult FluidSources::afterStep(PbfSolver& solver, double dt,
                                                 std::size_t max_particles) {
  StepResult result;
  if (!(dt > 0.0)) return result;
  if (!drains_.empty() && solver.size() > 0) {
    const auto& x = solver.positions();
    std::vector<std::uint8_t> inside(x.size(), 0);
    const std::size_t n = x.size();
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < n; ++i)
      for (const Drain& drain : drains_)
        if (drain.contains(x[i])) {
          inside[i] = 1;
          break;
        }
    result.drained = solver.removeParticles(inside);
    drained_ += result.drained;
  }
  for (std::size_t k = 0; k < emitters_.size(); ++k)
    result.emitted += emitLayers(solver, k, dt, max_particles, result);
  return result;
}

std::size_t FluidSources::emitLayers(PbfSolver& solver, std::size_t k, double dt,
                                     std::size_t max_particles, StepResult& result) {
  const Emitter& e = emitters_[k];
  EmitterState& s = state_[k];
  if (!s.placed) return 0;
  const float d = solver.params().particle_spacing;
  const double volume_budget = e.volume > 0.0f ? std::llround(double(e.volume) / (double(d) * d * d)) : -1.0;
  if (volume_budget >= 0.0 && double(s.emitted) >= volume_budget) return 0;
  // Open from `start` on: only the part of the step after it counts.
  // Scene::validate bounds the nozzle in spacings; a solver whose spacing shrank since
  // (reconfigure rebuilds, so only a direct caller) must not make a layer of millions.
  if (e.radius > kMaxEmitterRadiusInSpacings * d) return 0;
  const double t1 = solver.time(), t0 = t1 - dt;
  const double open = std::clamp(t1 - std::max(t0, double(e.start)), 0.0, dt);
  if (open <= 0.0) return 0;
  if (s.disc_spacing != d) {
    s.disc = discSites(e.radius, d);
    s.disc_spacing = d;
  }
  // Scene::validate bounds a rate's speed too; a direct caller's is capped here.
  const double speed = std::min<double>(kMaxEmitterSpeed, speedThrough(e, s.disc.size(), d));
  s.travel += speed * open;
  // More layers due than a step may add (a jet faster than kMaxLayersPerStep spacings per
  // step): the ones that left first, farthest from the nozzle, are dropped and the newest
  // kept, so the jet starts at the nozzle and its particles' speed shortens the next
  // adaptive step (CFL). Keeping the farthest put a 1000 m/s jet's layers metres ahead,
  // outside the container, at every step: it never emitted.
  const double due = std::floor(s.travel / d);
  if (due > kMaxLayersPerStep) {
    s.travel -= (due - kMaxLayersPerStep) * d;
    result.too_fast.push_back(k);
  }
  Eigen::Vector3f u, w;
  planeBasis(e.direction, u, w);
  // Only the sites that can land in the container: within its bounding sphere's reach in
  // the nozzle's plane (every layer's plane: they move along the normal). The others would
  // be dropped below as outside; a probe's 64 nozzles 2 m wide over a 0.3 m tank placed
  // 125 000 sites per nozzle and layer to keep a few hundred.
  std::vector<Eigen::Vector2f> reaching;
  const std::vector<Eigen::Vector2f>* disc = &s.disc;
  if (!solver.container().isEmpty()) {
    const Eigen::AlignedBox3f& box = solver.container();
    const Eigen::Vector3f centre = e.pose.inverse(Eigen::Isometry) * (solver.containerPose() * box.center()) -
                                   e.position;
    const Eigen::Vector2f in_plane(centre.dot(u), centre.dot(w));
    const float reach = 0.5f * box.diagonal().norm() + d;
    for (const Eigen::Vector2f& q : s.disc)
      if ((q - in_plane).squaredNorm() <= reach * reach) reaching.push_back(q);
    disc = &reaching;
  }
  std::vector<Eigen::Vector3f> sites;
  // Each layer is placed where it would be had it left the nozzle exactly when the layer
  // before it had gone d: the jet stays a lattice of spacing d along its direction.
  for (int layers = 0; s.travel >= d && layers < kMaxLayersPerStep; ++layers) {
    s.travel -= d;
    const Eigen::Vector3f centre = e.position + e.direction * static_cast<float>(s.travel);
    for (const Eigen::Vector2f& q : *disc) sites.push_back(e.pose * (centre + q.x() * u + q.y() * w));
  }
  s.travel = std::min(s.travel, double(d));
  if (sites.empty()) return 0;
  keepFreeSites(solver, sites);
  if (volume_budget >= 0.0)
    sites.resize(std::min<std::size_t>(sites.size(), static_cast<std::size_t>(volume_budget - double(s.emitted))));
  if (sites.empty()) return 0;
  if (solver.size() + sites.size() > max_particles) {
    result.held_by_limit.push_back(k);
    return 0;
  }
  const Eigen::Vector3f velocity = e.pose.linear() * (e.direction * static_cast<float>(speed));
  solver.addParticles(sites, std::vector<Eigen::Vector3f>(sites.size(), velocity));
  s.emitted += sites.size();
  emitted_ += sites.size();
  return sites.size();
}

SiteCount FluidSources::emitBlock(PbfSolver& solver, const FluidBlock& block,
                                  const Eigen::Isometry3f& pose, std::size_t max_particles) {
  const std::string err = validateBlock(block);
  if (!err.empty()) throw std::invalid_argument(err);
  if (!pose.matrix().allFinite()) throw std::invalid_argument("frame pose: not finite");
  const float d = solver.params().particle_spacing;
  const double bound = blockLatticePoints(block, d);
  const std::size_t room = max_particles > solver.size() ? max_particles - solver.size() : 0;
  if (!(bound <= kSiteWalkFactor * static_cast<double>(max_particles))) {
    std::ostringstream m;
    if (std::isfinite(bound))
      m << "the block holds about " << bound << " lattice sites at spacing " << d;
    else
      m << "the block holds more lattice sites than can be counted at spacing " << d;
    m << " m, more than the particle limit max_particles (" << max_particles
      << ") allows; nothing added";
    throw std::invalid_argument(m.str());
  }
  std::vector<Eigen::Vector3f> sites = blockSites(block, d);
  for (Eigen::Vector3f& p : sites) p = pose * p;
  SiteCount count = keepFreeSites(solver, sites);
  if (sites.empty()) {
    std::ostringstream m;
    m << "no free lattice site in the block (" << count.occupied << " occupied by fluid, "
      << count.in_solid << " inside solids, " << count.outside
      << " outside the container); nothing added";
    throw std::invalid_argument(m.str());
  }
  if (sites.size() > room) {
    std::ostringstream m;
    m << "adding " << sites.size() << " particles to " << solver.size()
      << " would exceed the particle limit max_particles (" << max_particles << "); nothing added";
    throw std::invalid_argument(m.str());
  }
  const Eigen::Vector3f velocity = pose.linear() * block.velocity;
  solver.addParticles(sites, std::vector<Eigen::Vector3f>(sites.size(), velocity));
  emitted_ += sites.size();
  return count;
}

}  // namespace pbf
