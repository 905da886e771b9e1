#pragma once
// The density the air side of a free surface would add were it fluid
// (SolverParams::free_surface_lend).
//
// A particle within h of the free surface sums only the fluid on its side: the top layer of
// a resting lattice sums 0.886 rho0 at h = 2d. Its own constraint is then slack (unilateral),
// so nothing holds it at its spacing: once the start lattice rearranges, the top layer sinks
// into the second layer's hollows until its truncated sum reaches rho0, and a resting tank
// loses ~1.5 % of its level (doc/calibration.md). Lent its missing density, the top layer
// keeps a constraint of its own, as the container's images keep the particles by a wall.
//
// How one-sided a neighbourhood is, is read from the constraint's gradient with respect to
// the particle itself, the container's images and the solids included, with the particle's
// own images counted once, as the lattice beyond a wall would be (in the constraint they
// count twice: they move with the particle): zero in a full neighbourhood and at a wall,
// largest at a free surface. Against a plane surface at depth s the continuum gives both
// sides in closed form: |grad C| = Pi(s) / S (Pi, the kernel's integral over the plane at
// distance s; S the lattice sum of SolverParams::densityMass) and the missing density
// Lambda(s) / S (Lambda, the kernel beyond s). The lend is Lambda at the depth whose Pi matches
// the gradient, scaled by one factor so that the start lattice's top layer is lent exactly
// its deficit (its discrete sum against the continuum's: 0.79 at h = 2d). A fresh lattice
// then sums to exactly rho0 at its free surface as everywhere else; its edges and corners,
// whose deficits the plane relation does not know, are lent less than they miss.
//
// A particle keeps its lend from step to step and it only ever shrinks: each step's first
// pass may lower it to what the particle's neighbourhood now shows, never raise it. A lend
// that follows the gradient both ways over-lends: a surface particle lifted by its lent
// constraint reads as more one-sided where it arrives (in the continuum the fluid's sum plus
// the lend does not depend on the depth at all), and the tank's level rose by 1 %. So a
// particle is lent what its neighbourhood lacked when it first entered the fluid, and loses
// it as it is buried; a free surface that forms later (a splash, a surge) is not lent, as
// without the option. That first measurement is taken where the step starts
// (NewParticleLends.cpp), before gravity pushes the fluid into the solids: measured at the
// predicted positions, a long step's compressed layers over the floor read as one-sided.

#include <vector>

namespace pbf {

class FreeSurfaceLend {
 public:
  // Not yet measured: a particle that has not started a step yet.
  static constexpr float kUnmeasured = -1.0f;

  FreeSurfaceLend(float spacing, float support_radius);

  // The lend, as a fraction of rho0, for a one-sided gradient of norm grad_norm [1/m].
  float fraction(float grad_norm) const;

  // A particle's lend [kg/m^3]: its first measurement (kept = kUnmeasured), or the smaller of
  // what it kept and what its one-sided gradient now shows (each step's first pass).
  float lowered(float kept, float grad_norm, float rest_density) const {
    const float now = rest_density * fraction(grad_norm);
    return kept < 0.0f ? now : (now < kept ? now : kept);
  }

  // The start lattice's top layer: what it misses, as a fraction of rho0 (0.1135 at h = 2d),
  // and its one-sided gradient [1/m] (0.387 / d): the point the lend is calibrated on.
  float latticeTopDeficit() const { return lattice_deficit_; }
  float latticeTopGradient() const { return lattice_gradient_ / d_; }

  float spacing() const { return d_; }
  float supportRadius() const { return h_; }

 private:
  float d_, h_;
  float lattice_deficit_ = 0.0f, lattice_gradient_ = 0.0f;  // gradient in units of 1/d
  float step_ = 1.0f;                                        // table step in units of 1/d
  std::vector<float> table_;                                 // lend fraction per step
};

}  // namespace pbf
