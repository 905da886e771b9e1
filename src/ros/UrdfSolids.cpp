#include "pbf_ros/ros/UrdfSolids.h"

#include <boost/regex.hpp>
#include <urdf/model.h>

#include <algorithm>
#include <iomanip>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <stdexcept>

#include "ConsoleBridgeCapture.h"
#include "pbf_ros/ros/EchoedText.h"
#include "pbf_ros/ros/MeshResource.h"

namespace pbf_ros {

namespace {

Eigen::Isometry3f isometry(const urdf::Pose& p) {
  Eigen::Isometry3f t = Eigen::Isometry3f::Identity();
  t.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z).cast<float>();
  t.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                   .normalized().toRotationMatrix().cast<float>();
  return t;
}

// Mesh grids by file and scale: a mesh used by several links is read and gridded once,
// and a file that failed is not tried again.
class MeshGrids {
 public:
  MeshGrids(const pbf::SignedDistanceGridOptions& options, std::size_t max_bytes_in_all)
      : options_(options), max_bytes_in_all_(max_bytes_in_all) {}

  // `flaw`: what is wrong with a mesh that still takes part ("" when nothing is).
  std::shared_ptr<const pbf::SignedDistanceGrid> get(const urdf::Mesh& m, std::string& error,
                                                     std::string& flaw) {
    std::ostringstream key;
    key << m.filename << " " << m.scale.x << " " << m.scale.y << " " << m.scale.z;
    auto found = cache_.find(key.str());
    if (found == cache_.end()) {
      found = cache_.emplace(key.str(), build(m)).first;
      if (found->second.grid) kept_bytes_ += found->second.grid->memoryBytes();
    }
    error = found->second.error;
    flaw = found->second.flaw;
    return found->second.grid;
  }

 private:
  struct Entry {
    std::shared_ptr<const pbf::SignedDistanceGrid> grid;
    std::string error, flaw;
  };

  Entry build(const urdf::Mesh& m) const {
    Entry e;
    pbf::TriangleMesh mesh;
    if (!loadMeshResource(m.filename, Eigen::Vector3d(m.scale.x, m.scale.y, m.scale.z), mesh, e.error))
      return e;
    if (mesh.triangles.size() > kMaxMeshTriangles) {
      e.error = std::to_string(mesh.triangles.size()) + " triangles, more than the " +
                std::to_string(kMaxMeshTriangles) + " a collision mesh may have (a visual mesh? give a " +
                "simplified one as collision geometry)";
      return e;
    }
    // What cannot bound a solid is said here; below, a grid can fail only for its size.
    if (const std::string bad = mesh.validate(); !bad.empty()) {
      e.error = "cannot bound a solid: " + bad;
      return e;
    }
    // Inside and outside of a mesh that is not closed are guesses near its holes: a solid
    // that stirs water at rest. It still takes part (robot meshes often have small gaps),
    // but the user is told.
    if (const std::size_t open = mesh.openEdges(); open > 0)
      e.flaw = "the mesh is not closed (" + std::to_string(open) + " open edges): near its holes " +
               "the solid's inside is a guess, and it may push water that should rest";
    // A mesh narrower than the grid's cell (half the particle spacing) is a point to the
    // fluid: it takes part, but a wrong <mesh scale> (millimetres read as metres, 1e-3 twice)
    // should not pass in silence.
    if (const float across = mesh.bounds().sizes().maxCoeff(); across < options_.cell) {
      std::ostringstream small;
      small << "the mesh is " << across << " m across at scale [" << m.scale.x << ", " << m.scale.y
            << ", " << m.scale.z << "], less than the solids' grid cell of " << options_.cell
            << " m (half the particle spacing): the fluid hardly feels it (is its scale right?)";
      e.flaw += (e.flaw.empty() ? "" : "; ") + small.str();
    }
    // What is left of the robot's budget for grids bounds this one too (9 bytes per node
    // while it is built, 4 kept).
    pbf::SignedDistanceGridOptions options = options_;
    const std::size_t left = max_bytes_in_all_ - std::min(kept_bytes_, max_bytes_in_all_);
    const bool budget_bounds = left / 4 * 9 < options.max_bytes;
    if (budget_bounds) options.max_bytes = left / 4 * 9;
    try {
      e.grid = pbf::SignedDistanceGrid::build(mesh, options);
    } catch (const std::exception& ex) {  // std::invalid_argument; bad_alloc just in case
      e.error = std::string("cannot bound a solid: ") + ex.what() +
                " (the node's cell is half of particle_spacing)";
      if (budget_bounds)
        e.error += " (the robot's mesh grids may take " + mib(max_bytes_in_all_) +
                   " in all, and the meshes before this one took " + mib(kept_bytes_) + ")";
    }
    return e;
  }

  static std::string mib(std::size_t bytes) {
    std::ostringstream out;
    out << std::setprecision(3) << double(bytes) / (1 << 20) << " MiB";
    return out.str();
  }

  pbf::SignedDistanceGridOptions options_;
  std::size_t max_bytes_in_all_;
  std::map<std::string, Entry> cache_;
  std::size_t kept_bytes_ = 0;  // the grids built so far
};

// The obstacle for one <collision>'s geometry; false, with `error`, when it is unusable.
bool toObstacle(const urdf::Geometry& g, MeshGrids& meshes, pbf::Obstacle& o, std::string& geometry,
                std::string& error, std::string& flaw) {
  switch (g.type) {
    case urdf::Geometry::BOX: {
      const auto& b = static_cast<const urdf::Box&>(g);
      o.shape = pbf::Obstacle::Shape::Box;
      o.half_extents = 0.5f * Eigen::Vector3d(b.dim.x, b.dim.y, b.dim.z).cast<float>();
      geometry = "box";
      break;
    }
    case urdf::Geometry::SPHERE:
      o.shape = pbf::Obstacle::Shape::Sphere;
      o.radius = static_cast<float>(static_cast<const urdf::Sphere&>(g).radius);
      geometry = "sphere";
      break;
    case urdf::Geometry::CYLINDER: {
      const auto& c = static_cast<const urdf::Cylinder&>(g);
      o.shape = pbf::Obstacle::Shape::Cylinder;  // both along z, centred on the origin
      o.radius = static_cast<float>(c.radius);
      o.half_length = static_cast<float>(0.5 * c.length);
      geometry = "cylinder";
      break;
    }
    case urdf::Geometry::MESH: {
      const auto& m = static_cast<const urdf::Mesh&>(g);
      geometry = "mesh '" + m.filename + "'";
      o.shape = pbf::Obstacle::Shape::Mesh;
      o.sdf = meshes.get(m, error, flaw);
      if (!o.sdf) return false;
      break;
    }
    default:
      error = "unknown geometry type";
      return false;
  }
  error = o.validate();
  return error.empty();
}

// The links that take part, in name order, with problems for what was asked but is missing.
// The regex is Boost's, not std::regex: a pattern with nested quantifiers, e.g.
// `(\w+_?)+_link`, backtracks exponentially, and std::regex_match then ran for minutes on
// a 35-character link name (the node hung at start-up and ignored SIGINT), or overflowed
// the stack on a very long name (SIGSEGV). Boost.Regex bounds a match's work and its own
// stack, and throws instead: the pattern is then refused, naming the link it choked on.
std::vector<urdf::LinkConstSharedPtr> selectLinks(const urdf::Model& model, const UrdfSolidsOptions& options,
                                                  std::vector<std::string>& problems) {
  std::unique_ptr<boost::regex> pattern;
  if (!options.link_regex.empty()) {
    try {
      pattern = std::make_unique<boost::regex>(options.link_regex, boost::regex::ECMAScript);
    } catch (const std::exception& e) {  // boost::regex_error
      problems.push_back("link regex '" + options.link_regex + "' is not a valid regular expression (" +
                         e.what() + "): no links selected");
      return {};
    }
  }
  std::string too_costly;  // the first link name the pattern could not be matched against
  auto matches = [&](const std::string& name) {
    if (!pattern) return true;
    try {
      return boost::regex_match(name, *pattern);
    } catch (const std::exception&) {  // the match's work or stack bound
      if (too_costly.empty()) too_costly = name;
      return false;
    }
  };
  auto refuseIfTooCostly = [&]() {
    if (too_costly.empty()) return false;
    problems.push_back("link regex '" + echoed(options.link_regex) + "' takes too long to match link '" +
                       echoed(too_costly) +
                       "' (nested repetitions such as (a+)+ backtrack without end): no links selected");
    return true;
  };
  std::vector<urdf::LinkConstSharedPtr> selected;
  if (!options.links.empty()) {
    std::set<std::string> seen;
    for (const std::string& name : options.links) {
      if (!seen.insert(name).second) continue;
      const urdf::LinkConstSharedPtr link = model.getLink(name);
      if (!link)
        problems.push_back("link '" + name + "' is not in the URDF of robot '" + model.getName() + "'");
      else if (link->collision_array.empty() && !link->collision)
        problems.push_back("link '" + name + "' has no collision geometry");
      else if (matches(name))
        selected.push_back(link);
    }
    if (refuseIfTooCostly()) return {};
    return selected;
  }
  for (const auto& [name, link] : model.links_)
    if (!(link->collision_array.empty() && !link->collision) && matches(name)) selected.push_back(link);
  if (refuseIfTooCostly()) return {};
  if (selected.empty())
    problems.push_back("no link of robot '" + model.getName() + "' has collision geometry" +
                       (pattern ? " and matches '" + options.link_regex + "'" : std::string()));
  return selected;
}

}  // namespace

std::vector<pbf::Obstacle> UrdfSolids::obstacles() const {
  std::vector<pbf::Obstacle> out;
  out.reserve(solids.size());
  for (const auto& s : solids) out.push_back(s.obstacle);
  return out;
}

std::size_t UrdfSolids::sdfBytes() const {
  std::set<const pbf::SignedDistanceGrid*> grids;
  std::size_t bytes = 0;
  for (const auto& s : solids)
    if (s.obstacle.sdf && grids.insert(s.obstacle.sdf.get()).second) bytes += s.obstacle.sdf->memoryBytes();
  return bytes;
}

UrdfSolids urdfSolids(const std::string& urdf_xml, const UrdfSolidsOptions& options) {
  UrdfSolids out;
  urdf::Model model;
  {
    ConsoleBridgeCapture log;
    if (!model.initString(urdf_xml)) {
      out.problems.push_back("the robot description is not a valid URDF" +
                             (log.text().empty() ? std::string() : ": " + log.text()));
      return out;
    }
    // The parser leaves out what it cannot read (a NaN box size, an infinite radius) and
    // only says so in its log: that is the one place the link is named.
    if (!log.text().empty())
      out.problems.push_back("the URDF parser left out what it could not read: " + log.text());
  }
  out.robot_name = model.getName();
  if (const std::string err = options.sdf.validate(); !err.empty()) {
    out.problems.push_back("mesh grid options: " + err + " (mesh links left out)");
  }
  MeshGrids meshes(options.sdf, options.max_mesh_grid_bytes);
  std::size_t left_over = 0;  // solids beyond options.max_solids
  std::string first_left_over;
  for (const urdf::LinkConstSharedPtr& link : selectLinks(model, options, out.problems)) {
    std::vector<urdf::CollisionSharedPtr> collisions = link->collision_array;
    if (collisions.empty() && link->collision) collisions.push_back(link->collision);
    for (std::size_t i = 0; i < collisions.size(); ++i) {
      const urdf::Collision& c = *collisions[i];
      UrdfSolid solid;
      solid.link = link->name;
      solid.name = link->name + "/" + (c.name.empty() ? "collision_" + std::to_string(i) : c.name);
      std::string error, flaw;
      if (!c.geometry) {
        out.problems.push_back("link '" + link->name + "' collision " + std::to_string(i) +
                               " has no geometry: left out");
        continue;
      }
      if (out.solids.size() == options.max_solids) {  // not even built: counted and left out
        ++left_over;
        if (left_over == 1) first_left_over = "link '" + link->name + "' collision " + std::to_string(i);
        continue;
      }
      if (!toObstacle(*c.geometry, meshes, solid.obstacle, solid.geometry, error, flaw)) {
        out.problems.push_back("link '" + link->name + "' collision " + std::to_string(i) + " (" +
                               solid.geometry + "): " + error + "; left out");
        continue;
      }
      if (!flaw.empty())
        out.problems.push_back("link '" + link->name + "' collision " + std::to_string(i) + " (" +
                               solid.geometry + "): " + flaw + "; it takes part");
      solid.obstacle.frame = link->name;
      solid.obstacle.offset = isometry(c.origin);
      solid.obstacle.pose = solid.obstacle.offset;  // until tf says where the link is
      out.solids.push_back(std::move(solid));
    }
  }
  if (left_over > 0)
    out.problems.push_back("robot '" + out.robot_name + "': at most " + std::to_string(options.max_solids) +
                           " solids take part (as many as a scene's obstacles); the " + std::to_string(left_over) +
                           " collision elements after them, from " + first_left_over + " on, are left out");
  return out;
}

}  // namespace pbf_ros
