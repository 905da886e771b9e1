#pragma once
// Everything solid the fluid meets in one step: the container (a box with a pose in the
// fluid frame, moved by the node when it is attached to a tf frame) and the obstacles.
//
// Obstacles lend density to the particles near them, as ghost fluid at rest beyond their
// surface (LatticeBoundary.h): exactly the missing density for a resting lattice at a face,
// an edge or a corner of a box obstacle; curved obstacles add to the flat-wall value what
// their curvature takes away. The container's walls lend through mirror images of the fluid
// instead, in the solver's passes (src/core/ContainerMirror.h). Container and obstacles
// keep particles out (project) and carry them along by friction (contact).
// Built once per pass from the solver's state; cheap to copy.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <vector>

#include "pbf_ros/core/LatticeBoundary.h"
#include "pbf_ros/core/Obstacle.h"

namespace pbf {

class SolidBoundaries {
 public:
  // `lattice` (for the spacing and support radius of the step) must outlive this object.
  SolidBoundaries(const Eigen::AlignedBox3f& container, const Eigen::Isometry3f& container_pose,
                  const std::vector<Obstacle>& obstacles, const LatticeBoundary& lattice,
                  float particle_radius);

  // Density fraction (multiply by rho0) lent by the obstacles near p, and its gradient with
  // respect to p. False (nothing added) when none is near: the common case, decided inline
  // when no obstacle is near the fluid at all (every particle of every pass asks).
  bool density(const Eigen::Vector3f& p, float& fraction, Eigen::Vector3f& gradient) const {
    return !near_.empty() && densityNearObstacles(p, fraction, gradient);
  }

  // p moved out of every obstacle and into the container, keeping particle_radius from
  // each surface. The container is applied last: no particle ever leaves it.
  Eigen::Vector3f project(const Eigen::Vector3f& p) const {
    return project(p, [](int, const Eigen::Vector3f&, const Eigen::Vector3f&) {});
  }
  // The same, telling report(solid, point, displacement) what each solid did (solid
  // numbering below). With a no-op report this is project() itself: one implementation.
  template <typename Report>
  Eigen::Vector3f project(const Eigen::Vector3f& p, Report&& report) const;

  // For a particle at p (after project): whether a surface lies within `reach` of it, its
  // unit normal, and how far that surface point moved during the step (from the previous
  // poses). Used for wall friction. `solid`, when given, receives which solid it is.
  bool contact(const Eigen::Vector3f& p, float reach, Eigen::Vector3f& normal,
               Eigen::Vector3f& surface_motion, int* solid = nullptr) const;

  // Solids by number, for what the fluid does to each (SolidWrench.h): the container's six
  // walls in its own frame (-x, +x, -y, +y, -z, +z), then obstacle k as kContainerFaces + k.
  static constexpr int kContainerFaces = 6;
  // Pushes out of a mesh per projection at most (project()).
  static constexpr int kMeshPushes = 3;
  std::size_t solidCount() const { return kContainerFaces + obstacles_->size(); }

  // density()'s gradient split by the obstacle that lends it: part(solid, gradient) for each
  // obstacle near p (solid numbering above).
  template <typename Part>
  void densityGradientParts(const Eigen::Vector3f& p, Part&& part) const;

  // Poses at the start of the step, for surface_motion (default: not moving).
  void setPreviousPoses(const Eigen::Isometry3f& container,
                        const std::vector<Eigen::Isometry3f>* obstacles) {
    prev_container_ = container;
    prev_obstacles_ = obstacles;
  }

  bool hasContainer() const { return has_container_; }

  // Leaves out the obstacles that cannot reach any particle inside `fluid` (their bounding
  // sphere, grown by the kernel's reach, misses the box): a robot's links far from the water
  // then cost nothing per particle, not even a distance check. All take part until called.
  void keepOnlyObstaclesNear(const Eigen::AlignedBox3f& fluid);

 private:
  bool densityNearObstacles(const Eigen::Vector3f& p, float& fraction, Eigen::Vector3f& gradient) const;
  bool boxDensity(const Obstacle& o, const Eigen::Vector3f& p, float& fraction,
                  Eigen::Vector3f& gradient) const;
  bool curvedDensity(const Obstacle& o, const Eigen::Vector3f& p, float& fraction,
                     Eigen::Vector3f& gradient) const;

  // project() beyond the common case (a clamp, inline): obstacles near, or a container
  // posed in the fluid frame. Kept out of line so that the clamp inlines into the passes.
  template <typename Report>
  [[gnu::noinline]] Eigen::Vector3f projectAroundSolids(const Eigen::Vector3f& p, Report&& report) const;
  // The container's clamp in its own frame; `q` is p in that frame.
  template <typename Report>
  Eigen::Vector3f clampIntoContainer(const Eigen::Vector3f& p, const Eigen::Vector3f& q,
                                     Report&& report) const;

  bool has_container_;
  bool posed_;  // container pose is not the identity
  Eigen::AlignedBox3f box_;
  // Where a particle centre may be, in the container's frame: radius_ inside each wall.
  Eigen::Vector3f lowest_, highest_;
  Eigen::Isometry3f pose_, inverse_;
  const std::vector<Obstacle>* obstacles_;
  std::vector<std::uint32_t> near_;  // indices of the obstacles that take part
  Eigen::Isometry3f prev_container_ = Eigen::Isometry3f::Identity();
  const std::vector<Eigen::Isometry3f>* prev_obstacles_ = nullptr;
  const LatticeBoundary* lattice_;
  float reach_, radius_;
};

// Most passes project every particle after every correction, and most scenes have no
// obstacle near the fluid and a container at rest: then it is a clamp, inlined into the
// pass (out of line, the call cost 6 % of a Jacobi step).
template <typename Report>
Eigen::Vector3f SolidBoundaries::project(const Eigen::Vector3f& p, Report&& report) const {
  if (!near_.empty() || posed_) return projectAroundSolids(p, report);
  return has_container_ ? clampIntoContainer(p, p, report) : p;
}

template <typename Report>
Eigen::Vector3f SolidBoundaries::projectAroundSolids(const Eigen::Vector3f& p_in, Report&& report) const {
  Eigen::Vector3f p = p_in;
  for (const std::uint32_t k : near_) {
    const Obstacle& o = (*obstacles_)[k];
    if ((p - o.pose.translation()).squaredNorm() > (o.boundingRadius() + radius_) * (o.boundingRadius() + radius_)) continue;
    // A mesh's distance is trilinear in a grid (SignedDistanceGrid.h): one push along its
    // normal lands short where the field bends (rims, edges), the more so the deeper the
    // particle was, so the push is repeated there. The other shapes' distances are exact.
    const int pushes = o.shape == Obstacle::Shape::Mesh ? kMeshPushes : 1;
    for (int q = 0; q < pushes; ++q) {
      Eigen::Vector3f n;
      const float s = o.signedDistance(p, n);
      if (s >= radius_) break;
      const Eigen::Vector3f push = (radius_ - s) * n;
      report(kContainerFaces + static_cast<int>(k), p, push);
      p += push;
    }
  }
  if (!has_container_) return p;
  if (!posed_) return clampIntoContainer(p, p, report);
  return pose_ * clampIntoContainer(p, Eigen::Vector3f(inverse_ * p), report);
}

template <typename Report>
Eigen::Vector3f SolidBoundaries::clampIntoContainer(const Eigen::Vector3f& p, const Eigen::Vector3f& q,
                                                    Report&& report) const {
  // Max, then min, as Eigen's cwiseMax/cwiseMin (x < lo ? lo : x): a NaN stays NaN, for the
  // step's finiteness check to reject.
  const Eigen::Vector3f clamped = q.cwiseMax(lowest_).cwiseMin(highest_);
  for (int a = 0; a < 3; ++a) {
    if (clamped[a] == q[a]) continue;
    Eigen::Vector3f push = Eigen::Vector3f::Zero();
    push[a] = clamped[a] - q[a];
    report(2 * a + (push[a] > 0.0f ? 0 : 1), p, posed_ ? Eigen::Vector3f(pose_.linear() * push) : push);
  }
  return clamped;
}

template <typename Part>
void SolidBoundaries::densityGradientParts(const Eigen::Vector3f& p, Part&& part) const {
  for (const std::uint32_t k : near_) {
    const Obstacle& o = (*obstacles_)[k];
    const float r = o.boundingRadius() + reach_;
    if ((p - o.pose.translation()).squaredNorm() > r * r) continue;
    float f = 0.0f;
    Eigen::Vector3f g = Eigen::Vector3f::Zero();
    const bool hit = o.shape == Obstacle::Shape::Box ? boxDensity(o, p, f, g) : curvedDensity(o, p, f, g);
    if (hit) part(kContainerFaces + static_cast<int>(k), g);
  }
}

}  // namespace pbf
