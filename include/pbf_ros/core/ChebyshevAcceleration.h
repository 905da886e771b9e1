#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace pbf {

class SolidBoundaries;

// Chebyshev semi-iterative acceleration of the Jacobi constraint iterations (Wang 2015, "A
// Chebyshev semi-iterative approach for accelerating projective and position-based
// dynamics"): after each correction, q^{k+1} = omega_{k+1} (q_jacobi^{k+1} - q^{k-1}) + q^{k-1},
// with omega from the Chebyshev recurrence for a Jacobi iteration of spectral radius rho.
// A Jacobi density solve converges slowly because a correction spreads one neighbourhood
// per iteration (a column's pressure takes many); the extrapolation carries it further.
// Positions only: an extrapolated over-push becomes an expansion that the projected solve
// (ConstraintPasses.cpp) takes back, which is why the solver projects whenever this is on.
// omega never exceeds its limit 2 / (1 + sqrt(1 - rho^2)): the recurrence starts above it
// (2 / (2 - rho^2): 1.82 for rho = 0.95, against a limit of 1.52), and every restart, i.e.
// right after the iteration misbehaved, would re-enter that phase. Uncapped, rho = 0.95
// gained energy at large steps and kept an overlapping start's energy (pbf_stress: fixed
// 1/60, 1/30, 1/15 s, overlapping starts); capped, the same cases pass and the 1 m^3 dam
// break converges as fast (doc/calibration.md).
class ChebyshevAcceleration {
 public:
  // Start of a solve from positions q0; rho in [0, 0.99] (SolverParams), 0: off.
  void begin(const std::vector<Eigen::Vector3f>& q0, float rho);
  bool isOn() const { return rho_ > 0.0f; }
  // After a Jacobi correction wrote q: extrapolate it in place, kept inside the solids.
  void extrapolate(std::vector<Eigen::Vector3f>& q, const SolidBoundaries& solids);
  // The error grew: a few plain Jacobi iterations again, then accelerate anew (a rho above
  // the true spectral radius would otherwise diverge).
  void restart() { since_start_ = 0; }
  // Particles were re-sorted in the middle of the solve (a neighbour-list rebuild).
  void reorder(const std::vector<std::uint32_t>& order, std::vector<Eigen::Vector3f>& scratch);
  // End of the solve: nothing to follow a later re-sort (capacity kept: no allocation).
  void end() {
    previous_.clear();
    current_.clear();
  }

 private:
  // Plain iterations before the first extrapolation: the first corrections remove the
  // local (high-frequency) error, which the recurrence is not built for.
  static constexpr int kPlainIterations = 2;
  float rho_ = 0.0f;
  float omega_ = 1.0f;
  float omega_limit_ = 1.0f;  // 2 / (1 + sqrt(1 - rho^2))
  int since_start_ = 0;
  std::vector<Eigen::Vector3f> previous_;  // q^{k-1}
  std::vector<Eigen::Vector3f> current_;   // q^k
};

}  // namespace pbf
