#include "pbf_ros/core/Scene.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>
#include <utility>

#include "pbf_ros/core/FluidSources.h"
#include "pbf_ros/core/RigidBody.h"

namespace pbf {

namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const std::string& origin, const std::string& key,
                       const std::string& expected) {
  throw SceneError(origin + ": key '" + key + "': expected " + expected);
}

float readFloat(const YAML::Node& n, const std::string& origin, const std::string& key) {
  if (!n.IsScalar()) fail(origin, key, "a number");
  try {
    const double v = n.as<double>();
    // The solver works in float: 1e39 is finite as a double but inf as a float.
    const float f = static_cast<float>(v);
    if (!std::isfinite(v) || !std::isfinite(f)) fail(origin, key, "a finite number (|x| < 3.4e38)");
    return f;
  } catch (const YAML::Exception&) {
    fail(origin, key, "a number (got '" + n.Scalar() + "')");
  }
}

int readInt(const YAML::Node& n, const std::string& origin, const std::string& key) {
  if (!n.IsScalar()) fail(origin, key, "an integer");
  try {
    return n.as<int>();
  } catch (const YAML::Exception&) {
    fail(origin, key, "an integer (got '" + n.Scalar() + "')");
  }
}

bool readBool(const YAML::Node& n, const std::string& origin, const std::string& key) {
  if (!n.IsScalar()) fail(origin, key, "true or false");
  try {
    return n.as<bool>();
  } catch (const YAML::Exception&) {
    fail(origin, key, "true or false (got '" + n.Scalar() + "')");
  }
}

Eigen::Vector3f readVec3(const YAML::Node& n, const std::string& origin, const std::string& key) {
  if (!n.IsSequence() || n.size() != 3) fail(origin, key, "a list of 3 numbers");
  Eigen::Vector3f v;
  for (int a = 0; a < 3; ++a) v[a] = readFloat(n[a], origin, key + "[" + std::to_string(a) + "]");
  return v;
}

const YAML::Node required(const YAML::Node& map, const std::string& name,
                          const std::string& origin, const std::string& key) {
  const YAML::Node n = map[name];
  if (!n) fail(origin, key, "to be present");
  return n;
}

// A map key as text; keys that are lists or maps (`? [a, b]`) are refused by name.
std::string keyName(const YAML::Node& key, const std::string& origin, const std::string& prefix) {
  if (!key.IsScalar()) {
    throw SceneError(origin + ": a key under '" + (prefix.empty() ? std::string("(top level)") : prefix) +
                     "' is not a plain name (got a " + (key.IsSequence() ? "list" : "map") + ")");
  }
  return key.Scalar();
}

// A key given twice in one map is an error in YAML that yaml-cpp lets through, and its
// readers disagree on which value wins (a lookup takes the first, a loop over the map
// applies both, so the last): refused by name, wherever it is. The walk is bounded in depth
// and in nodes: aliases share nodes, so a small file can name a node a billion times
// (a scene of 1000 blocks has ~10^4 nodes).
void refuseDuplicateKeys(const YAML::Node& node, const std::string& origin, const std::string& path,
                         std::size_t& budget, int depth = 0) {
  constexpr int kMaxDepth = 64;  // a scene is a few levels deep
  if (depth > kMaxDepth) throw SceneError(origin + ": '" + path + "' is nested deeper than 64 levels");
  if (budget-- == 0) throw SceneError(origin + ": more than 10^6 YAML nodes (aliases repeated?)");
  if (node.IsMap()) {
    std::set<std::string> seen;
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) continue;  // keyName() refuses it where the key is read
      const std::string& k = kv.first.Scalar();
      if (!seen.insert(k).second)
        throw SceneError(origin + ": key '" + (path.empty() ? k : path + "." + k) + "' is given twice");
      refuseDuplicateKeys(kv.second, origin, path.empty() ? k : path + "." + k, budget, depth + 1);
    }
  } else if (node.IsSequence()) {
    for (std::size_t i = 0; i < node.size(); ++i)
      refuseDuplicateKeys(node[i], origin, path + "[" + std::to_string(i) + "]", budget, depth + 1);
  }
}

void refuseDuplicateKeys(const YAML::Node& root, const std::string& origin) {
  std::size_t budget = 1000000;
  refuseDuplicateKeys(root, origin, "", budget);
}

std::string readString(const YAML::Node& n, const std::string& origin, const std::string& key) {
  if (!n.IsScalar()) fail(origin, key, "a string");
  return n.Scalar();
}

void checkKeys(const YAML::Node& map, const std::vector<std::string>& allowed,
               const std::string& origin, const std::string& prefix) {
  for (const auto& kv : map) {
    const std::string k = keyName(kv.first, origin, prefix);
    if (std::find(allowed.begin(), allowed.end(), k) == allowed.end()) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + a;
      throw SceneError(origin + ": unknown key '" + prefix + k + "' (known: " + list + ")");
    }
  }
}

// Every solver parameter a scene or parameter file may set, by name.
using Setter = std::function<void(SolverParams&, const YAML::Node&, const std::string&,
                                  const std::string&)>;
const std::map<std::string, Setter>& solverSetters() {
  static const std::map<std::string, Setter> setters = [] {
    std::map<std::string, Setter> m;
    auto f = [&m](const char* name, float SolverParams::*field) {
      m[name] = [field](SolverParams& p, const YAML::Node& n, const std::string& o,
                        const std::string& k) { p.*field = readFloat(n, o, k); };
    };
    auto i = [&m](const char* name, int SolverParams::*field) {
      m[name] = [field](SolverParams& p, const YAML::Node& n, const std::string& o,
                        const std::string& k) { p.*field = readInt(n, o, k); };
    };
    auto b = [&m](const char* name, bool SolverParams::*field) {
      m[name] = [field](SolverParams& p, const YAML::Node& n, const std::string& o,
                        const std::string& k) { p.*field = readBool(n, o, k); };
    };
    f("rest_density", &SolverParams::rest_density);
    f("particle_spacing", &SolverParams::particle_spacing);
    f("support_radius_factor", &SolverParams::support_radius_factor);
    m["gravity"] = [](SolverParams& p, const YAML::Node& n, const std::string& o,
                      const std::string& k) { p.gravity = readVec3(n, o, k); };
    f("time_step", &SolverParams::time_step);
    b("adaptive_time_step", &SolverParams::adaptive_time_step);
    f("cfl_factor", &SolverParams::cfl_factor);
    f("min_time_step", &SolverParams::min_time_step);
    f("max_time_step", &SolverParams::max_time_step);
    i("min_iterations", &SolverParams::min_iterations);
    i("max_iterations", &SolverParams::max_iterations);
    f("density_tolerance", &SolverParams::density_tolerance);
    f("cfm_relaxation", &SolverParams::cfm_relaxation);
    b("unilateral_constraint", &SolverParams::unilateral_constraint);
    b("free_surface_lend", &SolverParams::free_surface_lend);
    b("warm_start", &SolverParams::warm_start);
    f("chebyshev_rho", &SolverParams::chebyshev_rho);
    b("gauss_seidel", &SolverParams::gauss_seidel);
    f("gauss_seidel_omega", &SolverParams::gauss_seidel_omega);
    f("scorr_k", &SolverParams::scorr_k);
    f("scorr_n", &SolverParams::scorr_n);
    f("scorr_delta_q", &SolverParams::scorr_delta_q);
    b("wall_density", &SolverParams::wall_density);
    f("wall_friction", &SolverParams::wall_friction);
    f("xsph_viscosity", &SolverParams::xsph_viscosity);
    f("vorticity_epsilon", &SolverParams::vorticity_epsilon);
    f("neighbor_skin", &SolverParams::neighbor_skin);
    i("max_nan_retries", &SolverParams::max_nan_retries);
    f("max_speed_factor", &SolverParams::max_speed_factor);
    return m;
  }();
  return setters;
}

void applySolverNode(const YAML::Node& node, const std::string& origin, const std::string& prefix,
                     SolverParams& params) {
  if (!node.IsMap()) fail(origin, prefix.empty() ? "solver" : prefix, "a map of solver parameters");
  const auto& setters = solverSetters();
  for (const auto& kv : node) {
    const std::string k = keyName(kv.first, origin, prefix);
    const auto it = setters.find(k);
    // Parameters whose old form depended on dt or spacing were replaced, not reinterpreted.
    static const std::map<std::string, std::string> replaced = {
        {"cfm_epsilon", "cfm_relaxation (dimensionless, relative to the constraint's scale)"},
        {"xsph_c", "xsph_viscosity (a kinematic viscosity in m^2/s)"}};
    if (const auto r = replaced.find(k); r != replaced.end())
      throw SceneError(origin + ": solver parameter '" + prefix + k + "' was replaced by " + r->second);
    if (it == setters.end()) {
      std::string list;
      for (const auto& s : setters) list += (list.empty() ? "" : ", ") + s.first;
      throw SceneError(origin + ": unknown solver parameter '" + prefix + k + "' (known: " + list + ")");
    }
    it->second(params, kv.second, origin, prefix + k);
  }
  const std::string err = params.validate();
  if (!err.empty()) throw SceneError(origin + ": solver parameters: " + err);
}

FluidBlock readBlock(const YAML::Node& n, const std::string& origin, const std::string& key) {
  if (!n.IsMap()) fail(origin, key, "a map with 'box' or 'sphere'");
  checkKeys(n, {"box", "sphere", "velocity", "frame"}, origin, key + ".");
  FluidBlock b;
  if (n["box"] && n["sphere"]) fail(origin, key, "either 'box' or 'sphere', not both");
  if (const YAML::Node box = n["box"]) {
    checkKeys(box, {"min", "max"}, origin, key + ".box.");
    b.shape = FluidBlock::Shape::Box;
    b.min = readVec3(required(box, "min", origin, key + ".box.min"), origin, key + ".box.min");
    b.max = readVec3(required(box, "max", origin, key + ".box.max"), origin, key + ".box.max");
    if (!(b.min.array() < b.max.array()).all()) fail(origin, key + ".box", "min < max on every axis");
  } else if (const YAML::Node s = n["sphere"]) {
    checkKeys(s, {"center", "radius"}, origin, key + ".sphere.");
    b.shape = FluidBlock::Shape::Sphere;
    b.center = readVec3(required(s, "center", origin, key + ".sphere.center"), origin,
                        key + ".sphere.center");
    b.radius = readFloat(required(s, "radius", origin, key + ".sphere.radius"), origin,
                         key + ".sphere.radius");
    if (!(b.radius > 0.0f)) fail(origin, key + ".sphere.radius", "a number > 0");
  } else {
    fail(origin, key, "a 'box' or a 'sphere'");
  }
  if (const YAML::Node v = n["velocity"]) {
    b.velocity = readVec3(v, origin, key + ".velocity");
    // As for ~emit and the emitters: faster is a typo, and a speed near float's range would
    // make the first step's kinetic energy infinite.
    if (!(b.velocity.norm() <= kMaxEmitterSpeed))
      fail(origin, key + ".velocity", "a speed of at most " + std::to_string(int(kMaxEmitterSpeed)) + " m/s");
  }
  if (n["frame"]) {
    if (!n["frame"].IsScalar() || n["frame"].Scalar().empty()) fail(origin, key + ".frame", "a tf frame name");
    b.frame = n["frame"].Scalar();
  }
  return b;
}

Eigen::Isometry3f readPose(const YAML::Node& n, const std::string& origin, const std::string& key) {
  Eigen::Isometry3f pose = Eigen::Isometry3f::Identity();
  pose.translation() = readVec3(required(n, "center", origin, key + ".center"), origin, key + ".center");
  if (n["rpy"]) {
    const Eigen::Vector3f rpy = readVec3(n["rpy"], origin, key + ".rpy");
    pose.linear() = (Eigen::AngleAxisf(rpy.z(), Eigen::Vector3f::UnitZ()) *
                     Eigen::AngleAxisf(rpy.y(), Eigen::Vector3f::UnitY()) *
                     Eigen::AngleAxisf(rpy.x(), Eigen::Vector3f::UnitX())).toRotationMatrix();
  }
  return pose;
}

Obstacle readObstacle(const YAML::Node& n, const std::string& origin, const std::string& key) {
  if (!n.IsMap()) fail(origin, key, "a map with 'box', 'sphere', 'capsule' or 'cylinder'");
  checkKeys(n, {"box", "sphere", "capsule", "cylinder", "frame", "dynamic"}, origin, key + ".");
  Obstacle o;
  int shapes = 0;
  if (const YAML::Node b = n["box"]) {
    checkKeys(b, {"center", "half_extents", "rpy"}, origin, key + ".box.");
    o.shape = Obstacle::Shape::Box;
    o.offset = readPose(b, origin, key + ".box");
    o.half_extents = readVec3(required(b, "half_extents", origin, key + ".box.half_extents"), origin,
                              key + ".box.half_extents");
    ++shapes;
  }
  if (const YAML::Node sp = n["sphere"]) {
    checkKeys(sp, {"center", "radius"}, origin, key + ".sphere.");
    o.shape = Obstacle::Shape::Sphere;
    o.offset = readPose(sp, origin, key + ".sphere");
    o.radius = readFloat(required(sp, "radius", origin, key + ".sphere.radius"), origin, key + ".sphere.radius");
    ++shapes;
  }
  // Capsule and cylinder are both a radius and a half length along the local z axis.
  for (const auto& [name, shape] : {std::pair{"capsule", Obstacle::Shape::Capsule},
                                    std::pair{"cylinder", Obstacle::Shape::Cylinder}}) {
    const YAML::Node c = n[name];
    if (!c) continue;
    const std::string at = key + "." + name;
    checkKeys(c, {"center", "radius", "half_length", "rpy"}, origin, at + ".");
    o.shape = shape;
    o.offset = readPose(c, origin, at);
    o.radius = readFloat(required(c, "radius", origin, at + ".radius"), origin, at + ".radius");
    o.half_length =
        readFloat(required(c, "half_length", origin, at + ".half_length"), origin, at + ".half_length");
    ++shapes;
  }
  if (shapes != 1) fail(origin, key, "exactly one of 'box', 'sphere', 'capsule', 'cylinder'");
  if (n["frame"]) {
    if (!n["frame"].IsScalar() || n["frame"].Scalar().empty()) fail(origin, key + ".frame", "a tf frame name");
    o.frame = n["frame"].Scalar();
  }
  o.pose = o.offset;  // until the node knows where the frame is
  const std::string err = o.validate();
  if (!err.empty()) fail(origin, key, "usable sizes (" + err + ")");
  return o;
}

// `dynamic: {density: kg/m^3}` or `dynamic: {mass: kg}`, optionally `inertia: [ixx, iyy, izz]`
// (about its centre, in its axes; default: a uniform solid). The body starts at the shape's
// centre/rpy; `frame` names the tf frame the node publishes it on (default floating_<k>).
FloatingBodySpec readFloating(const YAML::Node& n, const std::string& origin, const std::string& key,
                              std::size_t index, Obstacle& o) {
  if (!n.IsMap()) fail(origin, key, "a map with 'density' or 'mass' (and optionally 'inertia')");
  checkKeys(n, {"density", "mass", "inertia"}, origin, key + ".");
  if (!n["density"] == !n["mass"]) fail(origin, key, "exactly one of 'density' [kg/m^3] or 'mass' [kg]");
  if (o.shape == Obstacle::Shape::Mesh) fail(origin, key, "a primitive shape (meshes cannot float yet)");
  FloatingBodySpec f;
  f.obstacle = index;
  const double volume = solidVolume(o);
  f.mass = n["mass"] ? readFloat(n["mass"], origin, key + ".mass")
                     : readFloat(n["density"], origin, key + ".density") * volume;
  if (!(f.mass > 0.0 && std::isfinite(f.mass))) fail(origin, key, "a positive mass or density");
  if (const YAML::Node i = n["inertia"]) {
    const Eigen::Vector3f diagonal = readVec3(i, origin, key + ".inertia");
    if (!(diagonal.array() > 0.0f).all()) fail(origin, key + ".inertia", "three positive moments [kg m^2]");
    f.inertia = diagonal.cast<double>().asDiagonal();
  } else {
    f.inertia = solidInertia(o, f.mass);
  }
  if (o.frame.empty()) o.frame = "floating_" + std::to_string(index);
  o.pose = o.offset;  // where it starts, in fluid_domain; the node publishes frame -> it
  o.offset = Eigen::Isometry3f::Identity();
  return f;
}

// `emitters:` entry: {position, direction, radius, speed | rate, volume, start, frame}.
Emitter readEmitter(const YAML::Node& n, const std::string& origin, const std::string& key) {
  if (!n.IsMap()) fail(origin, key, "a map with position, direction, radius and speed or rate");
  checkKeys(n, {"position", "direction", "radius", "speed", "rate", "volume", "start", "frame"}, origin,
            key + ".");
  Emitter e;
  e.position = readVec3(required(n, "position", origin, key + ".position"), origin, key + ".position");
  e.direction = readVec3(required(n, "direction", origin, key + ".direction"), origin, key + ".direction");
  e.radius = readFloat(required(n, "radius", origin, key + ".radius"), origin, key + ".radius");
  if (n["speed"]) e.speed = readFloat(n["speed"], origin, key + ".speed");
  if (n["rate"]) e.rate = readFloat(n["rate"], origin, key + ".rate");
  if (n["volume"]) e.volume = readFloat(n["volume"], origin, key + ".volume");
  if (n["start"]) e.start = readFloat(n["start"], origin, key + ".start");
  if (n["frame"]) {
    if (!n["frame"].IsScalar() || n["frame"].Scalar().empty()) fail(origin, key + ".frame", "a tf frame name");
    e.frame = n["frame"].Scalar();
  }
  if (!(e.direction.stableNorm() > 1e-6f)) fail(origin, key + ".direction", "a non-zero vector");
  if (!(e.radius > 0.0f)) fail(origin, key + ".radius", "a number > 0 [m]");
  if (n["speed"] && n["rate"]) fail(origin, key, "either 'speed' [m/s] or 'rate' [m^3/s], not both");
  if (n["speed"] && !(e.speed > 0.0f)) fail(origin, key + ".speed", "a number > 0 [m/s]");
  if (n["rate"] && !(e.rate > 0.0f)) fail(origin, key + ".rate", "a number > 0 [m^3/s]");
  if (!n["speed"] && !n["rate"]) fail(origin, key, "'speed' [m/s] or 'rate' [m^3/s]");
  if (n["volume"] && !(e.volume > 0.0f)) fail(origin, key + ".volume", "a number > 0 [m^3] (leave it out for no limit)");
  if (e.start < 0.0f) fail(origin, key + ".start", "a time >= 0 [s]");
  e.direction.stableNormalize();
  const std::string err = e.validate();  // what the checks above do not cover (speed bound)
  if (!err.empty()) {  // "field: expected what" -> fail(key.field, "what")
    std::string what = err.substr(err.find(':') + 2);
    if (what.rfind("expected ", 0) == 0) what = what.substr(9);
    fail(origin, key + "." + err.substr(0, err.find(':')), what);
  }
  return e;
}

// `drains:` entry: {box: {min, max}} or {sphere: {center, radius}}.
Drain readDrain(const YAML::Node& n, const std::string& origin, const std::string& key) {
  if (!n.IsMap()) fail(origin, key, "a map with 'box' or 'sphere'");
  checkKeys(n, {"box", "sphere"}, origin, key + ".");
  if (!n["box"] == !n["sphere"]) fail(origin, key, "exactly one of 'box' or 'sphere'");
  Drain d;
  if (const YAML::Node box = n["box"]) {
    if (!box.IsMap()) fail(origin, key + ".box", "a map with 'min' and 'max'");
    checkKeys(box, {"min", "max"}, origin, key + ".box.");
    d.shape = Drain::Shape::Box;
    d.min = readVec3(required(box, "min", origin, key + ".box.min"), origin, key + ".box.min");
    d.max = readVec3(required(box, "max", origin, key + ".box.max"), origin, key + ".box.max");
    if (!(d.min.array() < d.max.array()).all()) fail(origin, key + ".box", "min < max on every axis");
  } else {
    const YAML::Node s = n["sphere"];
    if (!s.IsMap()) fail(origin, key + ".sphere", "a map with 'center' and 'radius'");
    checkKeys(s, {"center", "radius"}, origin, key + ".sphere.");
    d.shape = Drain::Shape::Sphere;
    d.center = readVec3(required(s, "center", origin, key + ".sphere.center"), origin, key + ".sphere.center");
    d.radius = readFloat(required(s, "radius", origin, key + ".sphere.radius"), origin, key + ".sphere.radius");
    if (!(d.radius > 0.0f)) fail(origin, key + ".sphere.radius", "a number > 0 [m]");
  }
  return d;
}

// A list under `name` of at most `limit` entries, each read by `read`.
template <typename T, typename Read>
std::vector<T> readList(const YAML::Node& root, const char* name, std::size_t limit,
                        const std::string& origin, Read read) {
  std::vector<T> out;
  const YAML::Node list = root[name];
  if (!list) return out;
  if (!list.IsSequence()) fail(origin, name, "a list");
  if (list.size() > limit)
    fail(origin, name, "at most " + std::to_string(limit) + " entries (got " + std::to_string(list.size()) + ")");
  for (std::size_t i = 0; i < list.size(); ++i)
    out.push_back(read(list[i], origin, std::string(name) + "[" + std::to_string(i) + "]"));
  return out;
}

bool blockContains(const FluidBlock& b, const Eigen::Vector3f& p) {
  if (b.shape == FluidBlock::Shape::Box)
    return (p.array() >= b.min.array()).all() && (p.array() < b.max.array()).all();
  return (p - b.center).squaredNorm() <= b.radius * b.radius;
}

// Number of lattice points initialParticles() visits for a block (before overlaps and
// obstacles are taken out), in double: a tiny spacing must not overflow an int.
double latticePoints(const FluidBlock& b, float d) {
  const Eigen::Vector3f size = b.shape == FluidBlock::Shape::Box
                                   ? Eigen::Vector3f(b.max - b.min)
                                   : Eigen::Vector3f::Constant(2.0f * b.radius);
  double n = 1.0;
  for (int a = 0; a < 3; ++a) n *= std::max(1.0, std::floor(static_cast<double>(size[a]) / d));
  return n;
}

Scene parseScene(const std::string& text, const std::string& origin);

}  // namespace

BlockLattice blockLattice(const FluidBlock& b, float d, float slack) {
  Eigen::Vector3f lo, hi;
  if (b.shape == FluidBlock::Shape::Box) {
    lo = b.min;
    hi = b.max;
  } else {
    lo = b.center - Eigen::Vector3f::Constant(b.radius);
    hi = b.center + Eigen::Vector3f::Constant(b.radius);
  }
  const Eigen::Vector3i n =
      ((hi - lo) / d + Eigen::Vector3f::Constant(slack)).array().floor().cast<int>().max(1);
  // Centred in the block, so that round-off in (hi - lo) / d never adds a layer.
  const Eigen::Vector3f start =
      lo + 0.5f * ((hi - lo) - (n.cast<float>() * d)) + Eigen::Vector3f::Constant(0.5f * d);
  return {start, n};
}

Scene loadSceneString(const std::string& text, const std::string& origin) {
  try {
    return parseScene(text, origin);
  } catch (const YAML::Exception& e) {
    // Anything the checks above did not foresee still names the file, never escapes as a
    // YAML exception (a live scene change must be a refusal, not a failed callback).
    throw SceneError(origin + ": unusable YAML: " + e.what());
  }
}

namespace {

Scene parseScene(const std::string& text, const std::string& origin) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw SceneError(origin + ": not valid YAML: " + e.what());
  }
  refuseDuplicateKeys(root, origin);
  if (!root.IsMap()) throw SceneError(origin + ": expected a map at the top level");
  checkKeys(root, {"name", "description", "container", "container_frame", "domain_pose", "fluid",
                   "obstacles", "emitters", "drains", "solver"},
            origin, "");
  Scene s;
  s.source = origin;
  s.name = root["name"] ? readString(root["name"], origin, "name") : fs::path(origin).stem().string();

  const YAML::Node c = required(root, "container", origin, "container");
  if (!c.IsMap()) fail(origin, "container", "a map with 'min' and 'max'");
  checkKeys(c, {"min", "max"}, origin, "container.");
  const Eigen::Vector3f cmin = readVec3(required(c, "min", origin, "container.min"), origin, "container.min");
  const Eigen::Vector3f cmax = readVec3(required(c, "max", origin, "container.max"), origin, "container.max");
  if (!(cmin.array() < cmax.array()).all()) fail(origin, "container", "min < max on every axis");
  s.container = Eigen::AlignedBox3f(cmin, cmax);

  if (const YAML::Node pose = root["domain_pose"]) {
    checkKeys(pose, {"translation", "rpy"}, origin, "domain_pose.");
    if (pose["translation"]) s.domain_translation = readVec3(pose["translation"], origin, "domain_pose.translation");
    if (pose["rpy"]) s.domain_rpy = readVec3(pose["rpy"], origin, "domain_pose.rpy");
  }

  const YAML::Node fluid = required(root, "fluid", origin, "fluid");
  if (!fluid.IsSequence() || fluid.size() == 0) fail(origin, "fluid", "a non-empty list of blocks");
  if (fluid.size() > kMaxFluidBlocks)
    fail(origin, "fluid", "at most " + std::to_string(kMaxFluidBlocks) + " blocks (got " +
                              std::to_string(fluid.size()) + ")");
  for (std::size_t i = 0; i < fluid.size(); ++i)
    s.fluid.push_back(readBlock(fluid[i], origin, "fluid[" + std::to_string(i) + "]"));

  if (const YAML::Node obstacles = root["obstacles"]) {
    if (!obstacles.IsSequence()) fail(origin, "obstacles", "a list of obstacles");
    if (obstacles.size() > kMaxObstacles)
      fail(origin, "obstacles", "at most " + std::to_string(kMaxObstacles) + " obstacles (got " +
                                    std::to_string(obstacles.size()) + ")");
    for (std::size_t i = 0; i < obstacles.size(); ++i) {
      const std::string key = "obstacles[" + std::to_string(i) + "]";
      s.obstacles.push_back(readObstacle(obstacles[i], origin, key));
      if (const YAML::Node dynamic = obstacles[i]["dynamic"])
        s.floating.push_back(readFloating(dynamic, origin, key + ".dynamic", i, s.obstacles.back()));
    }
  }
  s.emitters = readList<Emitter>(root, "emitters", kMaxSceneEmitters, origin, readEmitter);
  s.drains = readList<Drain>(root, "drains", kMaxSceneDrains, origin, readDrain);
  if (const YAML::Node cf = root["container_frame"]) {
    if (!cf.IsScalar() || cf.Scalar().empty()) fail(origin, "container_frame", "a tf frame name");
    s.container_frame = cf.Scalar();
  }

  if (const YAML::Node solver = root["solver"]) applySolverNode(solver, origin, "solver.", s.solver);

  const std::string err = s.validate();
  if (!err.empty()) throw SceneError(origin + ": " + err);
  return s;
}

}  // namespace

Scene loadSceneFile(const std::string& path) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);
  if (ec || !fs::exists(status)) throw SceneError(path + ": no such scene file");
  if (fs::is_directory(status)) throw SceneError(path + ": is a directory, not a scene file");
  if (!fs::is_regular_file(status))
    throw SceneError(path + ": is not a regular file (a device or a pipe?), not a scene file");
  const std::uintmax_t size = fs::file_size(path, ec);
  if (ec) throw SceneError(path + ": cannot read the scene file's size: " + ec.message());
  if (size > kMaxSceneFileBytes) {
    throw SceneError(path + ": " + std::to_string(size) + " bytes; a scene file may have at most " +
                     std::to_string(kMaxSceneFileBytes) + " bytes");
  }
  std::ifstream in(path);
  if (!in) throw SceneError(path + ": cannot open the scene file");
  std::string text(static_cast<std::size_t>(size), '\0');
  in.read(&text[0], static_cast<std::streamsize>(size));
  text.resize(static_cast<std::size_t>(in.gcount()));
  return loadSceneString(text, path);
}

void applySolverYaml(const std::string& text, const std::string& origin, SolverParams& params) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw SceneError(origin + ": not valid YAML: " + e.what());
  }
  refuseDuplicateKeys(root, origin);
  SolverParams copy = params;  // all or nothing
  applySolverNode(root, origin, "", copy);
  params = copy;
}

std::string resolveScenePath(const std::string& name, const std::string& scenes_dir) {
  if (name.empty()) throw SceneError("scene: expected a scene name or a path, got an empty string");
  const bool is_path = name.find('/') != std::string::npos ||
                       (name.size() > 5 && name.substr(name.size() - 5) == ".yaml");
  const std::string path = is_path ? name : scenes_dir + "/" + name + ".yaml";
  std::error_code status_error;
  const fs::file_status status = fs::status(path, status_error);
  if (fs::is_regular_file(status)) return path;
  if (fs::is_directory(status))
    throw SceneError("scene '" + name + "': " + path + " is a directory, not a scene file");
  if (fs::exists(status))
    throw SceneError("scene '" + name + "': " + path + " is not a regular file (a device or a pipe?)");
  std::string known;
  std::error_code ec;
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(scenes_dir, ec))
    if (e.path().extension() == ".yaml") names.push_back(e.path().stem().string());
  std::sort(names.begin(), names.end());
  for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
  throw SceneError("scene '" + name + "': no such file " + path + " (known scenes in " + scenes_dir +
                   ": " + (known.empty() ? "none" : known) + ")");
}

bool Scene::floats(std::size_t index) const {
  for (const FloatingBodySpec& f : floating)
    if (f.obstacle == index) return true;
  return false;
}

std::string Scene::validate() const {
  std::ostringstream err;
  const std::string p = solver.validate();
  if (!p.empty()) return "solver: " + p;
  if (container.isEmpty()) return "container is empty";
  for (const FloatingBodySpec& f : floating) {
    if (f.obstacle >= obstacles.size()) return "a floating body names obstacle " + std::to_string(f.obstacle) + ", which does not exist";
    if (!(f.mass > 0.0 && std::isfinite(f.mass))) return "floating obstacle " + std::to_string(f.obstacle) + ": mass must be > 0";
    // Contact keeps a body inside the container only if it fits there: a 1 m raft in a
    // 0.6 x 0.4 m tank ended half outside it.
    const Obstacle& body = obstacles[f.obstacle];
    const Eigen::Vector3f extent = 2.0f * (body.pose.linear().cwiseAbs() * body.localHalfExtents());
    if ((extent.array() > container.sizes().array()).any()) {
      std::ostringstream e;
      e << "floating obstacle " << f.obstacle << " (" << extent.x() << " x " << extent.y() << " x " << extent.z()
        << " m as it starts) does not fit in the container (" << container.sizes().x() << " x "
        << container.sizes().y() << " x " << container.sizes().z() << " m)";
      return e.str();
    }
    const double volume = solidVolume(body);
    if (volume > 0.0 && f.mass / volume < kLightestFloatingDensityRatio * solver.rest_density) {
      std::ostringstream e;
      e << "floating obstacle " << f.obstacle << ": density " << f.mass / volume
        << " kg/m^3 is below " << 100.0 * kLightestFloatingDensityRatio << " % of the fluid's rest density ("
        << solver.rest_density << " kg/m^3); the fluid's explicit push is not stable on a body that light "
           "(README, floating bodies)";
      return e.str();
    }
    // A body lighter than one fluid particle is smaller than the fluid resolves, and each
    // particle's push kicks it faster than the particle moves: a probe's 1 mm ball of
    // 10^5 kg/m^3 (4e-4 kg) among d = 0.02 m particles (8e-3 kg) flew about the container
    // at up to 5.6 m/s and 6000 rad/s; at 4 mm (0.027 kg) it sank as it should.
    const double particle_mass = double(solver.rest_density) * std::pow(double(solver.particle_spacing), 3);
    if (f.mass < particle_mass) {
      std::ostringstream e;
      e << "floating obstacle " << f.obstacle << ": its mass " << f.mass
        << " kg is less than one fluid particle's (rest density x particle_spacing^3 = " << particle_mass
        << " kg): the fluid cannot resolve it; a larger or heavier body, or a finer particle_spacing";
      return e.str();
    }
    // Any mass distribution has principal moments that obey the triangle inequality.
    const Eigen::Vector3d moments = f.inertia.diagonal();
    for (int a = 0; a < 3; ++a)
      if (moments[a] > (moments[(a + 1) % 3] + moments[(a + 2) % 3]) * (1.0 + 1e-6)) {
        std::ostringstream e;
        e << "floating obstacle " << f.obstacle << ": inertia [" << moments[0] << ", " << moments[1] << ", "
          << moments[2] << "] kg m^2 is no body's: each principal moment must be at most the sum of the other two";
        return e.str();
      }
    // The density bound above, turned: a moment below what the solid would have at the lightest
    // density allowed is turned faster by the fluid's push than the explicit coupling can hold
    // (a probe's 100 kg capsule given [1e-9, 1e-9, 1e-9] kg m^2 moved at the speed cap).
    if (volume > 0.0) {
      const Eigen::Vector3d lightest =
          solidInertia(body, kLightestFloatingDensityRatio * solver.rest_density * volume).diagonal();
      for (int a = 0; a < 3; ++a)
        if (moments[a] < lightest[a] * (1.0 - 1e-6)) {
          std::ostringstream e;
          e << "floating obstacle " << f.obstacle << ": inertia [" << moments[0] << ", " << moments[1] << ", "
            << moments[2] << "] kg m^2 is below [" << lightest[0] << ", " << lightest[1] << ", " << lightest[2]
            << "], the solid's at " << 100.0 * kLightestFloatingDensityRatio
            << " % of the fluid's rest density; the fluid's explicit push is not stable on a body that "
               "light to turn (README, floating bodies)";
          return e.str();
        }
    }
  }
  const float d = solver.particle_spacing;
  const double cells = (container.sizes() / d).cast<double>().prod();
  if (cells > 5.0e8) {
    err << "container / particle_spacing gives " << cells << " lattice cells; expected at most 5e8";
    return err.str();
  }
  for (std::size_t i = 0; i < emitters.size(); ++i) {
    // A fixed nozzle outside the container could never emit anything: say so now.
    if (emitters[i].frame.empty() && !container.contains(emitters[i].position)) {
      err << "emitters[" << i << "].position is outside the container";
      return err.str();
    }
    if (emitters[i].radius > kMaxEmitterRadiusInSpacings * d) {
      err << "emitters[" << i << "].radius " << emitters[i].radius << " m is more than "
          << kMaxEmitterRadiusInSpacings << " particle spacings (" << d << " m)";
      return err.str();
    }
    // A rate is a speed through the nozzle's sites, bounded as a speed is (it was capped at
    // 1000 m/s in silence); and no jet faster than the fluid may go (the speed cap), which
    // would slow its particles at once.
    const double jet = emitterSpeed(emitters[i], d);
    const float cap = solver.speedCap(container.sizes().maxCoeff());
    if (jet > kMaxEmitterSpeed || (cap > 0.0f && jet > cap)) {
      err << "emitters[" << i << "]: " << jet << " m/s";
      if (emitters[i].rate > 0.0f) err << " (rate " << emitters[i].rate << " m^3/s at particle_spacing " << d << " m)";
      err << " is faster than ";
      if (jet > kMaxEmitterSpeed) err << kMaxEmitterSpeed << " m/s";
      else err << "the fluid's speed cap, " << cap << " m/s (max_speed_factor " << solver.max_speed_factor
               << " times the free-fall speed across the container)";
      return err.str();
    }
  }
  for (std::size_t i = 0; i < fluid.size(); ++i) {
    const FluidBlock& b = fluid[i];
    Eigen::AlignedBox3f bb = b.shape == FluidBlock::Shape::Box
                                 ? Eigen::AlignedBox3f(b.min, b.max)
                                 : Eigen::AlignedBox3f(b.center - Eigen::Vector3f::Constant(b.radius),
                                                       b.center + Eigen::Vector3f::Constant(b.radius));
    if (!container.contains(bb)) {
      err << "fluid[" << i << "] reaches outside the container";
      return err.str();
    }
    if ((bb.sizes().array() < d).any()) {
      err << "fluid[" << i << "] is thinner than one particle_spacing (" << d << " m)";
      return err.str();
    }
  }
  return "";
}

namespace {

// Calls visit(position, block index) for every initial particle, in order; stops early when
// visit returns false.
template <typename Visit>
void forEachInitialParticle(const Scene& scene, Visit visit) {
  const auto& fluid = scene.fluid;
  const auto& obstacles = scene.obstacles;
  const float d = scene.solver.particle_spacing;
  for (std::size_t bi = 0; bi < fluid.size(); ++bi) {
    const FluidBlock& b = fluid[bi];
    const auto [start, n] = blockLattice(b, d);
    for (int z = 0; z < n.z(); ++z)
      for (int y = 0; y < n.y(); ++y)
        for (int x = 0; x < n.x(); ++x) {
          const Eigen::Vector3f p = start + d * Eigen::Vector3f(x, y, z);
          if (!blockContains(b, p) && b.shape == FluidBlock::Shape::Sphere) continue;
          bool earlier = false;
          for (std::size_t k = 0; k < bi && !earlier; ++k) earlier = blockContains(fluid[k], p);
          if (earlier) continue;
          bool solid = false;
          Eigen::Vector3f normal;
          for (const Obstacle& o : obstacles) solid = solid || o.signedDistance(p, normal) < 0.5f * d;
          if (solid) continue;
          if (!visit(p, bi)) return;
        }
  }
}

}  // namespace

void Scene::initialParticles(std::vector<Eigen::Vector3f>& positions,
                             std::vector<Eigen::Vector3f>& velocities,
                             std::vector<std::uint32_t>* block_of) const {
  positions.clear();
  velocities.clear();
  if (block_of) block_of->clear();
  forEachInitialParticle(*this, [&](const Eigen::Vector3f& p, std::size_t block) {
    positions.push_back(p);
    velocities.push_back(fluid[block].velocity);
    if (block_of) block_of->push_back(static_cast<std::uint32_t>(block));
    return true;
  });
}

std::string Scene::checkParticleCount(std::size_t max_particles, const std::string& limit_name) const {
  // Walking the lattice costs time but no memory; beyond this many points it is refused
  // from the bound alone (overlaps and obstacles could only take a fraction out).
  constexpr double kWalkFactor = 4.0;
  const float d = solver.particle_spacing;
  double bound = 0.0;
  for (const FluidBlock& b : fluid) bound += latticePoints(b, d);
  std::ostringstream why;
  if (bound > kWalkFactor * static_cast<double>(max_particles)) {
    why << "scene '" << name << "' at particle_spacing " << d << " m needs about " << bound
        << " particles, more than " << limit_name << " (" << max_particles << ")";
    return why.str();
  }
  std::size_t count = 0;
  forEachInitialParticle(*this, [&](const Eigen::Vector3f&, std::size_t) {
    return ++count <= max_particles;
  });
  if (count > max_particles) {
    why << "scene '" << name << "' at particle_spacing " << d << " m needs more than "
        << max_particles << " particles (" << limit_name << ")";
  } else if (count == 0) {
    why << "scene '" << name << "' has no fluid left: its obstacles cover every fluid block";
    // Name what covers the first block's middle: with a robot in the scene it is often one
    // of its links (an obstacle on the link's frame), not a scene obstacle.
    if (!fluid.empty()) {
      const FluidBlock& b = fluid[0];
      const BlockLattice lattice = blockLattice(b, d);
      const Eigen::Vector3f middle = b.shape == FluidBlock::Shape::Box ? Eigen::Vector3f(0.5f * (b.min + b.max)) : b.center;
      const Eigen::Vector3f cell = ((middle - lattice.start) / d).array().round().max(0.0f).min(
          (lattice.n.array() - 1).max(0).cast<float>());
      const Eigen::Vector3f p = lattice.start + d * cell;
      for (std::size_t k = 0; k < obstacles.size(); ++k) {
        Eigen::Vector3f normal;
        if (!(obstacles[k].signedDistance(p, normal) < 0.5f * d)) continue;
        why << " (the middle of fluid[0] lies in obstacle " << k;
        if (!obstacles[k].frame.empty()) why << ", on frame '" << obstacles[k].frame << "'";
        why << ")";
        break;
      }
    }
  }
  return why.str();
}

const std::string& Scene::blockFrame(std::size_t index) const {
  const std::string& own = fluid.at(index).frame;
  return own.empty() ? container_frame : own;
}

}  // namespace pbf
