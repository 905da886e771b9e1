#pragma once
// Density that solid walls lend to the fluid, calibrated against the discrete lattice.
//
// A wall is modelled as ghost fluid at rest beyond it: the continuation of the fluid's own
// cubic lattice (spacing d), the layers fixed to the wall at d/2, 3d/2, ... behind it, as
// Akinci et al. (2012) boundary particles would be, and laterally aligned with the particle
// that looks at them. With the mass calibrated to the lattice (SolverParams::particleMass),
// a particle of a resting lattice then sums to exactly rho0 next to a flat wall, an edge or a
// corner: the ghost points are precisely the lattice points the walls cut away. The
// closed-form continuum fraction we used before over-lent 3.4 % at a wall, and adding walls
// independently counted the edge and corner overlaps two and three times.
//
// Everything is built from one function, the ghost sum over an octant of the lattice:
//   T(a, b, c) = (m / rho0) sum_{k,l,n >= 0} W(a + d/2 + k d, b + d/2 + l d, c + d/2 + n d),
// i.e. the lattice points beyond three planes at distances a, b, c from the particle (a
// negative distance: the particle is already beyond that plane). An argument at or below
// fullLine() takes the whole line along its axis; at or above reach() the octant is out of
// the kernel's support. Any axis-aligned box of ghost points (one wall, an edge, a corner,
// a box obstacle or a thin plate) is a signed sum of such octants (inclusion-exclusion), see
// Boundaries.cpp. T is tabulated once per support-radius factor (it only depends on h/d)
// and looked up trilinearly, with its exact derivatives tabulated alongside.

#include <Eigen/Core>
#include <memory>
#include <vector>

namespace pbf {

class LatticeBoundary {
 public:
  // spacing d [m] and support radius h [m] (h/d is what shapes the table).
  LatticeBoundary(float spacing, float support_radius);

  // T at s = (a, b, c) [m] and dT/ds [1/m]. Zero (and false) when any s >= reach().
  bool octant(const Eigen::Vector3f& s, float& value, Eigen::Vector3f& d_ds) const;

  // The flat-wall fraction F(s) = T(s, full, full) and dF/ds.
  float halfSpace(float s, float& d_ds) const;

  float fullLine() const { return full_line_ * d_; }  // [m]
  float reach() const { return reach_ * d_; }         // [m]
  float spacing() const { return d_; }
  float supportRadius() const { return h_; }

 private:
  float d_, h_;
  float full_line_, reach_, step_;  // in units of d
  int nodes_;                       // per axis
  // (T, dT/da, dT/db, dT/dc) per node in d units; shared by every solver with this h/d.
  std::shared_ptr<const std::vector<Eigen::Vector4f>> table_;
};

// Sum of the density kernel (Spiky, Kernels.h) over the infinite cubic lattice of spacing d,
// times d^3, for h = factor * d: 1 for a continuum, 1.23589 for factor 2 (the kernel's peak
// at r = 0 makes the self term alone 0.597). The particle mass that puts a
// lattice particle at exactly rho0 is rho0 d^3 / this.
double latticeKernelSum(double support_radius_factor);

// sum_j |grad W_ij|^2 * d^6 / latticeKernelSum^2 over the lattice: the constraint's own
// scale sum_j |grad_j C|^2 of a resting interior particle, times d^2 (dimensionless).
double latticeGradientScale(double support_radius_factor);

// The Jacobi solve's largest amplification on the cubic lattice: the largest eigenvalue of
// D^-1 A for the constraints' linearisation A = grad C grad C^T (D its diagonal), which on a
// lattice is a convolution; the maximum over wave vectors of |g(k)|^2 / D, g the Fourier sum
// of one constraint's gradients (sampled on 17^3 points of [0, pi]^3, which the lattice's
// symmetry makes the whole zone). A Jacobi correction overshoots by this much in its worst
// mode: 2.81 for factor 2, 4.18 for 2.5, 6.70 for 3, 14.4 for 4 (more neighbours, more
// overlapping corrections). Cached per factor.
double latticeJacobiAmplification(double support_radius_factor);

// Fraction of the density kernel (Spiky, support h) lying inside a ball of radius R whose surface is
// at distance s >= 0 from the particle: the continuum volume a sphere lends. For R -> inf it
// is the half-space fraction. Closed form (the kernel is polynomial in r). Double precision.
double continuumBallFraction(double s, double radius, double support_radius);
double continuumHalfSpaceFraction(double s, double support_radius);

// The density kernel (Spiky, support h) integrated over a plane at distance |s| from the
// particle [1/length]: what the particle adds, on average, to a horizontal slice of a column
// much wider than h (the free surface gauge, Metrics.h). Closed form, double precision.
double continuumPlaneIntegral(double s, double support_radius);

}  // namespace pbf
