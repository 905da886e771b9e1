#include "pbf_ros/core/SignedDistanceGrid.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace pbf {

namespace {

// Closest point to p on triangle abc (Ericson, Real-Time Collision Detection, 5.1.5),
// for non-degenerate triangles.
Eigen::Vector3f closestOnTriangle(const Eigen::Vector3f& p, const Eigen::Vector3f& a,
                                  const Eigen::Vector3f& b, const Eigen::Vector3f& c) {
  const Eigen::Vector3f ab = b - a, ac = c - a, ap = p - a;
  const float d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0f && d2 <= 0.0f) return a;
  const Eigen::Vector3f bp = p - b;
  const float d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0f && d4 <= d3) return b;
  const float vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0f && d1 >= 0.0f && d3 <= 0.0f) return a + d1 / (d1 - d3) * ab;
  const Eigen::Vector3f cp = p - c;
  const float d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0f && d5 <= d6) return c;
  const float vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0f && d2 >= 0.0f && d6 <= 0.0f) return a + d2 / (d2 - d6) * ac;
  const float va = d3 * d6 - d5 * d4;
  if (va <= 0.0f && (d4 - d3) >= 0.0f && (d5 - d6) >= 0.0f)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const float denom = 1.0f / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Orientation of the 2-D origin against the edge (x1,y1)->(x2,y2): twice the signed area,
// and a sign that is never 0 for distinct points. Exact zeros (the ray passes exactly
// through an edge or vertex) are broken by a fixed rule on the coordinates, so that of two
// triangles sharing that edge exactly one counts the crossing (simulation of simplicity).
int orientation(double x1, double y1, double x2, double y2, double& twice_area) {
  twice_area = y1 * x2 - x1 * y2;
  if (twice_area > 0.0) return 1;
  if (twice_area < 0.0) return -1;
  if (y2 > y1) return 1;
  if (y2 < y1) return -1;
  if (x1 > x2) return 1;
  if (x1 < x2) return -1;
  return 0;
}

// Whether the 2-D point (x0,y0) lies in the triangle of the three given points; if so, its
// barycentric weights w.
bool pointInTriangle2d(double x0, double y0, const double (&x)[3], const double (&y)[3],
                       double (&w)[3]) {
  const double x1 = x[0] - x0, x2 = x[1] - x0, x3 = x[2] - x0;
  const double y1 = y[0] - y0, y2 = y[1] - y0, y3 = y[2] - y0;
  const int s0 = orientation(x2, y2, x3, y3, w[0]);
  if (s0 == 0) return false;
  if (orientation(x3, y3, x1, y1, w[1]) != s0) return false;
  if (orientation(x1, y1, x2, y2, w[2]) != s0) return false;
  const double sum = w[0] + w[1] + w[2];
  if (sum == 0.0) return false;  // triangle seen edge-on: the ray does not cross it
  for (double& v : w) v /= sum;
  return true;
}

class GridBuilder {
 public:
  GridBuilder(const TriangleMesh& mesh, const Eigen::Vector3f& origin, const Eigen::Vector3i& dims,
              float cell, float band)
      : mesh_(mesh), origin_(origin), dims_(dims), cell_(cell), band_(band),
        count_(std::size_t(dims.x()) * dims.y() * dims.z()) {
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const auto& tri = mesh.triangles[t];
      const Eigen::Vector3f& a = mesh.vertices[tri[0]];
      if ((mesh.vertices[tri[1]] - a).cross(mesh.vertices[tri[2]] - a).squaredNorm() > 0.0f)
        usable_.push_back(static_cast<int>(t));  // zero-area triangles bound nothing
    }
  }

  std::vector<float> distances() {
    distance_.assign(count_, std::numeric_limits<float>::infinity());
    closest_.assign(count_, -1);
    nearTriangles();
    sweep();
    return distance_;
  }

  // Per node, how many of the three axis rays saw it inside (0..3).
  std::vector<std::uint8_t> insideVotes() const {
    std::vector<std::uint8_t> votes(count_, 0);
    for (int axis = 0; axis < 3; ++axis) voteAlong(axis, votes);
    return votes;
  }

 private:
  std::size_t index(int i, int j, int k) const {
    return (std::size_t(k) * dims_.y() + j) * dims_.x() + i;
  }
  Eigen::Vector3f position(int i, int j, int k) const {
    return origin_ + cell_ * Eigen::Vector3f(float(i), float(j), float(k));
  }
  const Eigen::Vector3f& vertex(int t, int corner) const {
    return mesh_.vertices[mesh_.triangles[t][corner]];
  }
  float distanceTo(int t, const Eigen::Vector3f& p) const {
    return (p - closestOnTriangle(p, vertex(t, 0), vertex(t, 1), vertex(t, 2))).norm();
  }

  // Exact distances for every node within band of a triangle's bounding box: every node
  // within band of the surface is then exact (its closest triangle was among those tried).
  void nearTriangles() {
    for (const int t : usable_) {
      Eigen::Vector3f lo = vertex(t, 0).cwiseMin(vertex(t, 1)).cwiseMin(vertex(t, 2));
      Eigen::Vector3f hi = vertex(t, 0).cwiseMax(vertex(t, 1)).cwiseMax(vertex(t, 2));
      lo.array() -= band_;
      hi.array() += band_;
      Eigen::Vector3i first, last;
      for (int a = 0; a < 3; ++a) {
        first[a] = std::max(0, int(std::floor((lo[a] - origin_[a]) / cell_)));
        last[a] = std::min(dims_[a] - 1, int(std::ceil((hi[a] - origin_[a]) / cell_)));
      }
      for (int k = first.z(); k <= last.z(); ++k)
        for (int j = first.y(); j <= last.y(); ++j)
          for (int i = first.x(); i <= last.x(); ++i) {
            const std::size_t n = index(i, j, k);
            const float d = distanceTo(t, position(i, j, k));
            if (d < distance_[n]) {
              distance_[n] = d;
              closest_[n] = t;
            }
          }
    }
  }

  // Nodes beyond the band (deep inside, the grid's corners): fast sweeping in the eight
  // diagonal directions, twice, each node trying its upwind neighbours' closest triangles.
  void sweep() {
    for (int round = 0; round < 2; ++round)
      for (int dir = 0; dir < 8; ++dir) {
        const int si = dir & 1 ? -1 : 1, sj = dir & 2 ? -1 : 1, sk = dir & 4 ? -1 : 1;
        const int i0 = si > 0 ? 0 : dims_.x() - 1, j0 = sj > 0 ? 0 : dims_.y() - 1,
                  k0 = sk > 0 ? 0 : dims_.z() - 1;
        for (int k = k0; k >= 0 && k < dims_.z(); k += sk)
          for (int j = j0; j >= 0 && j < dims_.y(); j += sj)
            for (int i = i0; i >= 0 && i < dims_.x(); i += si) relax(i, j, k, si, sj, sk);
      }
  }

  void relax(int i, int j, int k, int si, int sj, int sk) {
    const std::size_t n = index(i, j, k);
    if (distance_[n] <= band_) return;  // exact already
    const Eigen::Vector3f p = position(i, j, k);
    for (int m = 1; m < 8; ++m) {
      const int ni = i - (m & 1 ? si : 0), nj = j - (m & 2 ? sj : 0), nk = k - (m & 4 ? sk : 0);
      if (ni < 0 || nj < 0 || nk < 0 || ni >= dims_.x() || nj >= dims_.y() || nk >= dims_.z()) continue;
      const int t = closest_[index(ni, nj, nk)];
      if (t < 0 || t == closest_[n]) continue;
      const float d = distanceTo(t, p);
      if (d < distance_[n]) {
        distance_[n] = d;
        closest_[n] = t;
      }
    }
  }

  // Rays along `axis` through every row of nodes: the crossings with the mesh, sorted; a
  // node with an odd number of crossings before it is inside.
  void voteAlong(int axis, std::vector<std::uint8_t>& votes) const {
    const int b = (axis + 1) % 3, c = (axis + 2) % 3;
    std::vector<std::vector<double>> rows(std::size_t(dims_[b]) * dims_[c]);
    for (const int t : usable_) {
      double xb[3], xc[3], xa[3];
      for (int v = 0; v < 3; ++v) {  // in cells, relative to the grid origin: exact-ish doubles
        const Eigen::Vector3f g = (vertex(t, v) - origin_) / cell_;
        xa[v] = g[axis];
        xb[v] = g[b];
        xc[v] = g[c];
      }
      const int jb0 = std::max(0, int(std::ceil(std::min({xb[0], xb[1], xb[2]}))));
      const int jb1 = std::min(dims_[b] - 1, int(std::floor(std::max({xb[0], xb[1], xb[2]}))));
      const int jc0 = std::max(0, int(std::ceil(std::min({xc[0], xc[1], xc[2]}))));
      const int jc1 = std::min(dims_[c] - 1, int(std::floor(std::max({xc[0], xc[1], xc[2]}))));
      for (int jc = jc0; jc <= jc1; ++jc)
        for (int jb = jb0; jb <= jb1; ++jb) {
          double w[3];
          if (pointInTriangle2d(jb, jc, xb, xc, w))
            rows[std::size_t(jc) * dims_[b] + jb].push_back(w[0] * xa[0] + w[1] * xa[1] + w[2] * xa[2]);
        }
    }
    Eigen::Vector3i node;
    for (int jc = 0; jc < dims_[c]; ++jc)
      for (int jb = 0; jb < dims_[b]; ++jb) {
        std::vector<double>& hits = rows[std::size_t(jc) * dims_[b] + jb];
        std::sort(hits.begin(), hits.end());
        std::size_t passed = 0;
        node[b] = jb;
        node[c] = jc;
        for (int ja = 0; ja < dims_[axis]; ++ja) {
          while (passed < hits.size() && hits[passed] < ja) ++passed;
          node[axis] = ja;
          votes[index(node.x(), node.y(), node.z())] += passed % 2;
        }
      }
  }

  const TriangleMesh& mesh_;
  Eigen::Vector3f origin_;
  Eigen::Vector3i dims_;
  float cell_, band_;
  std::size_t count_;
  std::vector<int> usable_;
  std::vector<float> distance_;
  std::vector<int> closest_;
};

}  // namespace

std::string SignedDistanceGridOptions::validate() const {
  std::ostringstream err;
  if (!(std::isfinite(cell) && cell > 0.0f)) err << "SDF cell must be finite and > 0 (got " << cell << ")";
  else if (!(std::isfinite(band) && band >= cell))
    err << "SDF band must be finite and at least one cell (got " << band << " for cell " << cell << ")";
  return err.str();
}

std::shared_ptr<const SignedDistanceGrid> SignedDistanceGrid::build(
    const TriangleMesh& mesh, const SignedDistanceGridOptions& options) {
  if (std::string err = options.validate(); !err.empty()) throw std::invalid_argument(err);
  if (std::string err = mesh.validate(); !err.empty()) throw std::invalid_argument(err);

  const Eigen::AlignedBox3f bounds = mesh.bounds();
  const Eigen::Vector3f lo = bounds.min(), hi = bounds.max();
  std::shared_ptr<SignedDistanceGrid> grid(new SignedDistanceGrid());
  grid->cell_ = options.cell;
  grid->band_ = options.band;
  grid->origin_ = lo - Eigen::Vector3f::Constant(options.band);
  const Eigen::Vector3f extent = hi - lo + Eigen::Vector3f::Constant(2.0f * options.band);
  // Counted in doubles before any int holds them: a mesh scaled to 1e9 m has more nodes on
  // one axis than an int counts, and the wrapped count passed the memory check below. (The
  // quotient stays a float's, as it was, so every grid that fits keeps its nodes.)
  Eigen::Array3d nodes;
  for (int a = 0; a < 3; ++a) nodes[a] = double(std::ceil(extent[a] / options.cell)) + 1.0;
  const double count = nodes.prod();
  // Building needs the values, the closest triangles and the votes: 9 bytes per node.
  if (!(count * 9.0 <= double(options.max_bytes))) {
    std::ostringstream err;
    err << "SDF grid of " << nodes.transpose() << " nodes (cell " << options.cell << " m over "
        << extent.transpose() << " m) would need " << count * 9.0 / (1 << 20) << " MiB, over the limit of "
        << double(options.max_bytes) / (1 << 20) << " MiB: use a larger cell or a smaller mesh";
    throw std::invalid_argument(err.str());
  }
  grid->dims_ = nodes.cast<int>().matrix();

  GridBuilder builder(mesh, grid->origin_, grid->dims_, options.cell, options.band);
  grid->values_ = builder.distances();
  const std::vector<std::uint8_t> votes = builder.insideVotes();
  for (std::size_t n = 0; n < grid->values_.size(); ++n) {
    if (votes[n] >= 2) grid->values_[n] = -grid->values_[n];
    // On the surface itself a ray may graze a face and disagree harmlessly; count only
    // disagreement where the sign matters.
    grid->ambiguous_nodes_ += (votes[n] == 1 || votes[n] == 2) && std::abs(grid->values_[n]) > options.cell;
  }
  grid->values_.shrink_to_fit();
  grid->mesh_ = mesh;
  grid->bounding_radius_ = mesh.boundingRadius();
  return grid;
}

float SignedDistanceGrid::signedDistance(const Eigen::Vector3f& q, Eigen::Vector3f& normal) const {
  const Eigen::Vector3f g = (q - origin_) / cell_;
  const Eigen::Vector3f max_g = (dims_ - Eigen::Vector3i::Ones()).cast<float>();
  const Eigen::Vector3f gc = g.cwiseMax(0.0f).cwiseMin(max_g);
  const float beyond = (g - gc).norm() * cell_;  // > 0 only outside the grid
  Eigen::Vector3i i0;
  Eigen::Vector3f f;
  for (int a = 0; a < 3; ++a) {
    i0[a] = std::min(int(gc[a]), dims_[a] - 2);
    f[a] = gc[a] - float(i0[a]);
  }
  float v[2][2][2];
  for (int dk = 0; dk < 2; ++dk)
    for (int dj = 0; dj < 2; ++dj)
      for (int di = 0; di < 2; ++di) v[di][dj][dk] = node(i0.x() + di, i0.y() + dj, i0.z() + dk);
  // Trilinear value and its exact gradient within the cell.
  const float fx = f.x(), fy = f.y(), fz = f.z(), gx = 1 - fx, gy = 1 - fy, gz = 1 - fz;
  const float x00 = gx * v[0][0][0] + fx * v[1][0][0], x10 = gx * v[0][1][0] + fx * v[1][1][0];
  const float x01 = gx * v[0][0][1] + fx * v[1][0][1], x11 = gx * v[0][1][1] + fx * v[1][1][1];
  const float y0 = gy * x00 + fy * x10, y1 = gy * x01 + fy * x11;
  const float value = gz * y0 + fz * y1;
  Eigen::Vector3f grad;
  grad.z() = y1 - y0;
  grad.y() = gz * (x10 - x00) + fz * (x11 - x01);
  grad.x() = gz * (gy * (v[1][0][0] - v[0][0][0]) + fy * (v[1][1][0] - v[0][1][0])) +
             fz * (gy * (v[1][0][1] - v[0][0][1]) + fy * (v[1][1][1] - v[0][1][1]));
  const float len = grad.norm();
  // A flat spot (on a ridge of the field, deep inside): any direction will do; pick +z.
  normal = len > 1e-12f ? Eigen::Vector3f(grad / len) : Eigen::Vector3f::UnitZ();
  return value + beyond;
}

std::size_t SignedDistanceGrid::memoryBytes() const {
  return sizeof(*this) + values_.capacity() * sizeof(float) +
         mesh_.vertices.capacity() * sizeof(Eigen::Vector3f) +
         mesh_.triangles.capacity() * sizeof(Eigen::Vector3i);
}

}  // namespace pbf
