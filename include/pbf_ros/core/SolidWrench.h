#pragma once
// The force and torque the fluid exerts on each solid in a step (issue 12, part 2).
//
// Every displacement a solid causes a particle in the step (its share of the density
// constraint, lambda_i grad Psi_solid; the projection that keeps particles out; wall
// friction) changes that particle's momentum by m dx / dt (velocities are position
// differences over dt). The solid feels the reaction: F = -m sum dx / dt^2, the average force
// over the step, and torque = -m sum (x - o) x dx / dt^2 about the solid's origin o.
// Fluid-fluid corrections are equal and opposite pair by pair, so over the fluid the solids'
// forces and gravity are all that changes its momentum: at rest they sum to its weight.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <vector>

namespace pbf {

struct Obstacle;

struct Wrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();   // [N]
  Eigen::Vector3d torque = Eigen::Vector3d::Zero();  // [N m], about the stated point

  Wrench& operator+=(const Wrench& w) {
    force += w.force;
    torque += w.torque;
    return *this;
  }
  // The same wrench with its torque taken about `to` instead of `from`.
  Wrench movedTo(const Eigen::Vector3d& from, const Eigen::Vector3d& to) const {
    Wrench w = *this;
    w.torque += (from - to).cross(force);
    return w;
  }
  bool allFinite() const { return force.allFinite() && torque.allFinite(); }
};

// What the fluid did to every solid in the last step, in fluid_domain axes.
struct SolidWrenches {
  bool valid = false;  // tracking was on for the step
  // The container's walls, in its own frame's order -x, +x, -y, +y, -z, +z, torque about
  // the container pose's origin; `container` is their sum.
  std::array<Wrench, 6> container_faces;
  Wrench container;
  // One per obstacle, torque about the obstacle pose's origin (pose.translation()).
  std::vector<Wrench> obstacles;
};

// Per-thread sums of what solids did to particles during one step attempt.
class WrenchAccumulator {
 public:
  // Slots for `solids` solids (container faces first, then obstacles) and `threads` threads.
  void reset(std::size_t solids, int threads);
  // Thread `thread` saw solid `solid` move the particle at `x` by `dx` [m].
  void add(int thread, int solid, const Eigen::Vector3f& x, const Eigen::Vector3f& dx) {
    double* s = &sums_[(static_cast<std::size_t>(thread) * stride_ + static_cast<std::size_t>(solid)) * 6];
    const Eigen::Vector3d xd = x.cast<double>(), d = dx.cast<double>();
    const Eigen::Vector3d m = xd.cross(d);
    s[0] += d.x(), s[1] += d.y(), s[2] += d.z();
    s[3] += m.x(), s[4] += m.y(), s[5] += m.z();
  }
  // Reactions for particles of mass `mass` over a step of `dt`, torques about the solids'
  // origins (`container_origin`, each obstacle's pose).
  SolidWrenches result(double mass, double dt, const Eigen::Vector3d& container_origin,
                       const std::vector<Obstacle>& obstacles) const;

 private:
  std::size_t solids_ = 0, stride_ = 0;  // stride_ pads a thread's block to whole cache lines
  int threads_ = 0;
  std::vector<double> sums_;  // [thread][solid][dx, x cross dx]
};

}  // namespace pbf
