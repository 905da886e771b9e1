#pragma once
// A mesh solid's signed distance, sampled once on a regular grid in the solid's local frame
// and interpolated trilinearly, so that the boundary code can ask a mesh what it asks a box:
// the distance to the surface (negative inside) and the outward normal.
//
// Built at load time, never per step: exact point-triangle distances for every grid node
// within `band` of the surface, fast sweeping (closest triangle passed on to the neighbours)
// for the nodes beyond it, and the sign by ray parity along x, y and z with a majority vote,
// so that one ray grazing an edge, or a small hole in a mesh that is not quite closed, does
// not flip a node. The grid covers the mesh's bounding box plus `band` on every side.
// Immutable once built: obstacles share it through a shared_ptr<const>.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "pbf_ros/core/TriangleMesh.h"

namespace pbf {

struct SignedDistanceGridOptions {
  // Node spacing [m]. Trilinear interpolation is exact on flat faces; near edges and
  // corners the error is a fraction of a cell. A particle spacing / 2 is a good choice.
  float cell = 0.005f;
  // Margin around the mesh [m], also the distance up to which node values are exact
  // point-triangle distances. Must cover the kernel support radius (the boundary lends
  // density up to h from the surface); h + one particle spacing is a good choice.
  float band = 0.03f;
  // Refuse grids larger than this (a huge mesh at a fine cell would eat the memory).
  std::size_t max_bytes = std::size_t(256) << 20;

  // Empty when usable; otherwise what is wrong.
  std::string validate() const;
};

class SignedDistanceGrid {
 public:
  // Throws std::invalid_argument with the mesh's or the options' validate() message, or
  // when the grid would exceed max_bytes.
  static std::shared_ptr<const SignedDistanceGrid> build(const TriangleMesh& mesh,
                                                         const SignedDistanceGridOptions& options);

  // Signed distance from q (local frame) to the surface, negative inside, and the unit
  // outward normal (the normalised gradient of the interpolated field). Beyond the grid,
  // the distance to the grid's box is added: an upper bound that is >= band there.
  float signedDistance(const Eigen::Vector3f& q, Eigen::Vector3f& normal) const;
  // Whether q lies inside the solid (the sign, without the interpolation).
  bool inside(const Eigen::Vector3f& q) const { Eigen::Vector3f n; return signedDistance(q, n) < 0.0f; }

  // Largest |vertex| of the mesh: a sphere about the local origin containing the solid.
  float boundingRadius() const { return bounding_radius_; }
  float cell() const { return cell_; }
  float band() const { return band_; }
  const Eigen::Vector3i& nodes() const { return dims_; }
  Eigen::Vector3f origin() const { return origin_; }  // local position of node (0, 0, 0)
  // The mesh it was built from (kept for markers, so they show what the solver uses).
  const TriangleMesh& mesh() const { return mesh_; }
  // Memory held: the grid plus the kept mesh [bytes].
  std::size_t memoryBytes() const;
  // Grid nodes farther than a cell from the surface whose three rays disagreed on the
  // sign (0 for a closed mesh; a hole in the mesh shows here, outvoted where it can be).
  std::size_t ambiguousNodes() const { return ambiguous_nodes_; }

 private:
  SignedDistanceGrid() = default;
  float node(int i, int j, int k) const {
    return values_[(static_cast<std::size_t>(k) * dims_.y() + j) * dims_.x() + i];
  }

  TriangleMesh mesh_;
  Eigen::Vector3f origin_ = Eigen::Vector3f::Zero();
  Eigen::Vector3i dims_ = Eigen::Vector3i::Zero();
  float cell_ = 0.0f, band_ = 0.0f, bounding_radius_ = 0.0f;
  std::vector<float> values_;  // x fastest
  std::size_t ambiguous_nodes_ = 0;
};

}  // namespace pbf
