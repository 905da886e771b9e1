#pragma once
// The container's walls as mirror images of the fluid (Takeda et al. 1994; Cummins & Rudman
// 1999 for the pressure): beyond each wall lies the reflection of the fluid in front of it,
// beyond an edge or a corner the reflection across two or three walls. A particle near a wall
// sums its neighbours' images (and its own) like neighbours, in the density and in both
// constraint passes.
//
// Why images and not ghost fluid fixed to the wall (the lattice table that obstacles use,
// LatticeBoundary.h): both lend exactly the missing density to a resting lattice, but fixed
// ghost fluid carries no pressure gradient. In the delta-p pass a neighbour j pushes with
// lambda_i + lambda_j; ghost fluid could only push with lambda_i, so a particle near a wall
// missed the wall side's share of the push that holds it up against gravity. In a resting
// tank the columns along the side walls (the edges most: three quarters of their support is
// beyond the walls) slid down at 0.1-0.15 m/s while the middle rose, a circulation that never
// settled. An image carries its original's lambda: the pressure continues symmetrically
// beyond the wall, as it does at a free-slip wall, and every column is held alike.
//
// Images are exact at flat walls, edges and corners; the pairs (i, image of j) and
// (j, image of i) are equally far apart, so the passes stay symmetric and identical for any
// thread count. The image of j is never closer to i than j is, so i's neighbour list holds
// every image within h. A container thinner than 2h on an axis mirrors only the nearer wall
// of that axis.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdint>

#include "NeighborSums.h"

namespace pbf {

class ContainerMirror {
 public:
  // At most 7 reflections reach a particle: three walls, three edges, one corner.
  static constexpr int kMaxReflections = 7;

  // An empty box: no container, no images. Every particle is kept at least `radius` (half a
  // spacing) inside each wall, the predictions included (PbfSolver::attemptStep), so the image
  // of j is at least s_i + radius from i: only walls nearer than h - radius lend anything.
  // That leaves out the second layer of a resting lattice, whose images all lie at h or
  // beyond. (A particle beyond a wall would be pushed further out by its own image.)
  ContainerMirror(const Eigen::AlignedBox3f& box, const Eigen::Isometry3f& pose, float support_radius,
                  float radius)
      : on_(!box.isEmpty()),
        posed_(!pose.isApprox(Eigen::Isometry3f::Identity(), 1e-7f)),
        box_(box),
        inverse_(pose.inverse(Eigen::Isometry)),
        reach_(support_radius - radius) {
    if (on_) buildTable(pose);
  }

  bool isOn() const { return on_; }

  // The reflections whose images can lie within h of a particle at x (world frame): every
  // non-empty set of the walls that near (one per axis). Returns how many.
  int reflections(const Eigen::Vector3f& x, Reflection (&out)[kMaxReflections]) const {
    if (!on_) return 0;
    const Eigen::Vector3f q = posed_ ? Eigen::Vector3f(inverse_ * x) : x;
    int side[3];  // 0: no wall near, 1: the min wall, 2: the max wall
    int near_axes = 0;
    for (int a = 0; a < 3; ++a) {
      const float to_min = q[a] - box_.min()[a], to_max = box_.max()[a] - q[a];
      side[a] = std::min(to_min, to_max) >= reach_ ? 0 : (to_max < to_min ? 2 : 1);
      if (side[a] != 0) near_axes |= 1 << a;
    }
    if (near_axes == 0) return 0;  // the common case
    int count = 0;
    for (int set = 1; set < 8; ++set)
      if ((set & near_axes) == set) out[count++] = table_[code(set, side)];
    return count;
  }

  // fn(j, r, r2, self, walls) for every image within h of particle i, j being the particle
  // reflected (i itself when self), r = x_i - image, r2 = |r|^2, walls as in Reflection.
  // Scalar: for the rare passes (wrench tracking); the hot passes use NeighborSums.
  template <typename Fn>
  void forEachImage(std::size_t i, const NeighborArrays& a, float h2, Fn&& fn) const {
    Reflection refl[kMaxReflections];
    const float* P = a.position;
    const int count = reflections(Eigen::Vector3f(P[3 * i], P[3 * i + 1], P[3 * i + 2]), refl);
    for (int k = 0; k < count; ++k) {
      auto visit = [&](std::uint32_t j, bool self) {
        const Eigen::Vector3f r = imageOffset(refl[k], P, i, j);
        const float r2 = r.squaredNorm();
        if (r2 < h2) fn(j, r, r2, self, refl[k].walls);
      };
      visit(static_cast<std::uint32_t>(i), true);
      for (std::uint32_t e = a.offset[i]; e < a.offset[i + 1]; ++e) visit(a.index[e], false);
    }
  }

  // x_i - image of x_j under the reflection.
  static Eigen::Vector3f imageOffset(const Reflection& r, const float* P, std::size_t i, std::size_t j) {
    const float* m = r.m;
    const float x = P[3 * j], y = P[3 * j + 1], z = P[3 * j + 2];
    return Eigen::Vector3f(P[3 * i] - (m[0] * x + m[1] * y + m[2] * z + r.b[0]),
                           P[3 * i + 1] - (m[3] * x + m[4] * y + m[5] * z + r.b[1]),
                           P[3 * i + 2] - (m[6] * x + m[7] * y + m[8] * z + r.b[2]));
  }

  // The container frame's axis a in the world frame (for splitting a push among walls).
  Eigen::Vector3f axis(int a) const { return inverse_.linear().row(a).transpose(); }

 private:
  // A set of walls, one side per reflected axis, as a base-3 number (side 1 or 2 per axis).
  static int code(int set, const int (&side)[3]) {
    int c = 0;
    for (int a = 2; a >= 0; --a) c = 3 * c + ((set >> a) & 1 ? side[a] : 0);
    return c;
  }

  // Every reflection the box has (26 sets of walls), once per pass instead of per particle.
  // In the container frame: y_a = 2 plane_a - q_a on the reflected axes. In the world frame
  // that is the affine map x -> A S A^T x + (t - A S A^T t + A c), A and t the pose,
  // S = diag(+-1), c = 2 plane on the reflected axes.
  void buildTable(const Eigen::Isometry3f& pose) {
    const Eigen::Matrix3f A = pose.linear();
    for (int c = 1; c < 27; ++c) {
      Eigen::Vector3f s = Eigen::Vector3f::Ones(), shift = Eigen::Vector3f::Zero();
      Reflection& r = table_[c];
      r.walls = 0;
      for (int a = 0, rest = c; a < 3; ++a, rest /= 3) {
        const int side = rest % 3;
        if (side == 0) continue;
        s[a] = -1.0f;
        shift[a] = 2.0f * (side == 2 ? box_.max()[a] : box_.min()[a]);
        r.walls |= 1 << (2 * a + side - 1);
      }
      const Eigen::Matrix3f M = A * s.asDiagonal() * A.transpose();
      const Eigen::Vector3f b = pose.translation() - M * pose.translation() + A * shift;
      for (int row = 0; row < 3; ++row) {
        for (int col = 0; col < 3; ++col) r.m[3 * row + col] = M(row, col);
        r.b[row] = b[row];
      }
    }
  }

  bool on_, posed_;
  Eigen::AlignedBox3f box_;
  Eigen::Isometry3f inverse_;
  float reach_;
  Reflection table_[27];  // by code(); entry 0 (no wall) unused
};

}  // namespace pbf
