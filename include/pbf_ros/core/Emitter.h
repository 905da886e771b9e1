#pragma once
// A nozzle that adds fluid while the simulation runs (scene key `emitters:`): a disc of
// `radius` at `position`, facing `direction`, from which fluid leaves at `speed`. It emits
// whole layers of the solver's cubic lattice (one spacing d apart along the jet, so the jet
// starts at rest density with the calibrated particle mass), each layer once the fluid
// before it has moved d. FluidSources.h runs it.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>

namespace pbf {

// Faster than this is a typo, not a nozzle [m/s] (the solver caps particle speeds far lower).
constexpr float kMaxEmitterSpeed = 1000.0f;

struct Emitter {
  Eigen::Vector3f position = Eigen::Vector3f::Zero();    // centre of the opening [m]
  Eigen::Vector3f direction = -Eigen::Vector3f::UnitZ(); // where the jet goes (normalised)
  float radius = 0.02f;  // of the opening [m]; the layer holds the lattice sites within it
  // Exit speed [m/s]. Alternatively `rate`, a volume flow [m^3/s], from which the speed
  // follows (rate / (sites per layer * d^2), at most kMaxEmitterSpeed); exactly one of the
  // two is > 0.
  float speed = 0.0f;
  float rate = 0.0f;
  float volume = 0.0f;   // total to emit [m^3] (rounded to whole particles); 0 = no limit
  float start = 0.0f;    // simulated time at which it opens [s]
  // tf frame the nozzle is attached to ("" = fixed in fluid_domain): position and
  // direction are given in it; `pose` is where that frame is (the node sets it from tf).
  std::string frame;
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();

  // Empty when usable; otherwise what is wrong, naming the field ("radius: ...").
  std::string validate() const;
};

}  // namespace pbf
