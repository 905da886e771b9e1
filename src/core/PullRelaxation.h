#pragma once
// How far a correction that pulls particles together goes (internal to pbf_core).

namespace pbf {

// A density correction that pulls (a two-sided constraint's expanded particle, or a
// projected solve taking back a push) is taken at half its Newton step, IISPH's relaxed
// Jacobi (omega = 0.5, Ihmsen et al. 2014); pushes are not relaxed.
//
// Why pulls only: a push opens its pairs, where Spiky's gradient is weaker, so the
// linearised step undershoots and the next iteration finishes it; a pull closes them,
// where the gradient is stronger, so the step overshoots, and a particle with few
// neighbours (a surface or a splash) has a small gradient sum that only epsilon bounds.
// At a full step the pulls, with every neighbour pulling at once (Jacobi) or over-relaxed
// (the sweeps' omega), fed energy into the fluid: the two-sided constraint blew up a tank
// at rest with the Jacobi solve and the dam break with the sweeps, up to the speed cap
// (test_core_calibration, TwoSidedConstraintRelaxesItsPullsAndStaysCalm). A projected
// Jacobi pass that takes back in full oscillates likewise: every neighbour takes back too,
// as every one pushed.
constexpr float kPullRelaxation = 0.5f;

}  // namespace pbf
