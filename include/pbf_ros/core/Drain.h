#pragma once
// A region that removes the fluid that enters it (scene key `drains:`): a box or a sphere,
// fixed in fluid_domain. FluidSources.h runs it after every step.

#include <Eigen/Core>
#include <string>

namespace pbf {

struct Drain {
  enum class Shape { Box, Sphere };
  Shape shape = Shape::Box;
  Eigen::Vector3f min = Eigen::Vector3f::Zero();     // Box [m]
  Eigen::Vector3f max = Eigen::Vector3f::Zero();     // Box [m]
  Eigen::Vector3f center = Eigen::Vector3f::Zero();  // Sphere [m]
  float radius = 0.0f;                               // Sphere [m]

  bool contains(const Eigen::Vector3f& p) const {
    if (shape == Shape::Box) return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
    return (p - center).squaredNorm() <= radius * radius;
  }
  // Empty when usable; otherwise what is wrong, naming the field.
  std::string validate() const;
};

}  // namespace pbf
