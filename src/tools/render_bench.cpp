// pbf_render_bench: milliseconds per render pass for dam-break-like blocks of particles.
// No ROS. Each frame renders image + depth (what the node publishes) at 640x480 by
// default; the first frames are a warm-up (shader JIT, allocation) and are not counted.
//
//   pbf_render_bench [--backend osmesa|egl] [--frames N] [--warmup N] [--width W]
//                    [--height H] [--filter narrow|bilateral|none] [--sigma RADII]
//                    [--counts 20000,80000] [--shaders DIR] [--png DIR]
//
// Each scene is measured three ways: image + depth (what the node renders when both topics
// have subscribers) drawing every particle; the same drawing only the surface particles
// (fewer than 24 neighbours within h = 2 spacings, counted here the way the node has them
// from the solver; inside the block a particle has about 30); and depth alone, surface
// particles only.

#include <sys/resource.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include "ToolArguments.h"
#include "pbf_ros/render/FluidRenderer.h"
#include "pbf_ros/render/ImageWriter.h"

namespace {

struct Options {
  std::string backend = "osmesa";
  int frames = 30, warmup = 5, width = 640, height = 480;
  std::string filter = "narrow";
  float sigma = -1;  // filter sigma in particle radii; < 0: the renderer's default
  std::vector<int> counts = {20000, 80000};
  std::string shader_dir = PBF_SHADER_SOURCE_DIR;
  std::string png_dir;
};

// Options' counts and sizes are ints.
int intIn(const std::string& option, const std::string& text, long lo, long hi) {
  return static_cast<int>(pbf_tools::integerIn(option, text, lo, hi));
}

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--backend") o.backend = value();
    else if (arg == "--frames") o.frames = intIn(arg, value(), 1, 100000);
    else if (arg == "--warmup") o.warmup = intIn(arg, value(), 0, 100000);
    // The node's own limit (Fluid.cfg render_width, render_height).
    else if (arg == "--width") o.width = intIn(arg, value(), 1, 4096);
    else if (arg == "--height") o.height = intIn(arg, value(), 1, 4096);
    else if (arg == "--filter") o.filter = value();
    else if (arg == "--sigma") o.sigma = static_cast<float>(pbf_tools::finitePositive(arg, value()));
    else if (arg == "--shaders") o.shader_dir = value();
    else if (arg == "--png") o.png_dir = value();
    else if (arg == "--counts") {
      o.counts.clear();
      std::stringstream list(value());
      // At most the node's ~max_particles default.
      for (std::string item; std::getline(list, item, ',');) o.counts.push_back(intIn(arg, item, 1, 1000000));
      if (o.counts.empty()) throw std::invalid_argument("--counts expects a list such as 20000,80000");
    } else {
      throw std::invalid_argument("unknown argument " + arg +
                                  " (see the comment at the top of render_bench.cpp)");
    }
  }
  return o;
}

// A dam-break block standing in the corner of a 1 m x 0.6 m container: a lattice of
// spacing 1 cm, 2:1.25:1 in x:y:z, jittered by 10 % of the spacing as a settled fluid is.
std::vector<Eigen::Vector3f> damBreakBlock(int count, float spacing) {
  const double unit = std::cbrt(count / (2.0 * 1.25));
  const int nz = std::max(1, static_cast<int>(std::round(unit)));
  const int ny = std::max(1, static_cast<int>(std::round(1.25 * unit)));
  const int nx = (count + ny * nz - 1) / (ny * nz);
  std::mt19937 random(7);
  std::uniform_real_distribution<float> jitter(-0.1f * spacing, 0.1f * spacing);
  std::vector<Eigen::Vector3f> points;
  points.reserve(count);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx && static_cast<int>(points.size()) < count; ++i)
        points.emplace_back((i + 0.5f) * spacing + jitter(random),
                            (j + 0.5f) * spacing + jitter(random),
                            (k + 0.5f) * spacing + jitter(random));
  return points;
}

// Neighbours within `radius` of each point, by brute force over a hashed grid.
std::vector<std::uint32_t> neighborCounts(const std::vector<Eigen::Vector3f>& points,
                                          float radius) {
  std::unordered_map<std::int64_t, std::vector<std::uint32_t>> cells;
  auto key = [radius](const Eigen::Vector3f& p, int dx, int dy, int dz) {
    const std::int64_t x = static_cast<std::int64_t>(std::floor(p.x() / radius)) + dx;
    const std::int64_t y = static_cast<std::int64_t>(std::floor(p.y() / radius)) + dy;
    const std::int64_t z = static_cast<std::int64_t>(std::floor(p.z() / radius)) + dz;
    return (x * 73856093) ^ (y * 19349663) ^ (z * 83492791);
  };
  for (std::uint32_t i = 0; i < points.size(); ++i) cells[key(points[i], 0, 0, 0)].push_back(i);
  std::vector<std::uint32_t> counts(points.size(), 0);
  for (std::uint32_t i = 0; i < points.size(); ++i)
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto cell = cells.find(key(points[i], dx, dy, dz));
          if (cell == cells.end()) continue;
          for (std::uint32_t j : cell->second)
            if (j != i && (points[i] - points[j]).squaredNorm() < radius * radius) ++counts[i];
        }
  return counts;
}

// CPU time of the whole process (every llvmpipe thread included), in milliseconds.
double processCpuMilliseconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto ms = [](const timeval& t) { return t.tv_sec * 1e3 + t.tv_usec * 1e-3; };
  return ms(usage.ru_utime) + ms(usage.ru_stime);
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0 : s / v.size();
}
double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    const Options o = parse(argc, argv);
    pbf::RenderOptions render_options;
    if (o.filter == "narrow") render_options.filter = pbf::DepthFilter::NarrowRange;
    else if (o.filter == "bilateral") render_options.filter = pbf::DepthFilter::Bilateral;
    else if (o.filter == "none") render_options.filter = pbf::DepthFilter::None;
    else throw std::invalid_argument("--filter must be narrow, bilateral or none");
    if (o.sigma >= 0) render_options.filter_sigma_in_radii = o.sigma;

    pbf::FluidRenderer renderer(pbf::createGlBackend(o.backend), o.shader_dir, render_options);
    std::printf("backend %s: %s\n", o.backend.c_str(), renderer.glDescription().c_str());

    const float spacing = 0.01f, radius = 0.5f * spacing;
    pbf::RenderCamera camera;
    camera.width = o.width;
    camera.height = o.height;
    // Looking down at the block from a corner of the container, as a user would set it up;
    // the 20k block covers about a tenth of the image, the 80k one about a quarter.
    camera.camera_to_world =
        pbf::lookAt(Eigen::Vector3f(0.95f, -0.45f, 0.5f), Eigen::Vector3f(0.3f, 0.2f, 0.08f));
    const pbf::RenderRequest image_and_depth{true, true, false, false};
    const pbf::RenderRequest depth_only{false, true, false, false};

    std::printf("%dx%d, filter %s, %d frames after %d warm-up, ms per pass (mean / median)\n",
                o.width, o.height, o.filter.c_str(), o.frames, o.warmup);
    std::printf("%9s %-13s %9s %13s %13s %13s %13s %13s %13s %13s %13s %10s\n", "particles",
                "request", "in depth", "cull+upload", "depth", "thickness", "filter",
                "normals", "composite", "readback", "total", "cpu/frame");
    for (int run = 0; run < 3 * static_cast<int>(o.counts.size()); ++run) {
      const int count = o.counts[run / 3];
      const bool surface_only = run % 3 != 0;
      const bool with_image = run % 3 != 2;
      const std::vector<Eigen::Vector3f> particles = damBreakBlock(count, spacing);
      const std::vector<std::uint32_t> counts =
          surface_only ? neighborCounts(particles, 2.0f * spacing) : std::vector<std::uint32_t>{};
      pbf::RenderOptions run_options = render_options;
      run_options.surface_particles_only = surface_only;
      renderer.setOptions(run_options);
      pbf::RenderOutput out;
      std::vector<double> t[8];
      double cpu_start = 0;
      for (int frame = 0; frame < o.warmup + o.frames; ++frame) {
        if (frame == o.warmup) cpu_start = processCpuMilliseconds();
        renderer.render(particles, radius, camera, with_image ? image_and_depth : depth_only,
                        out, surface_only ? &counts : nullptr);
        if (frame < o.warmup) continue;
        const pbf::RenderTimings& s = out.timings;
        const double values[8] = {s.cull_upload, s.depth,     s.thickness, s.filter,
                                  s.normals,     s.composite, s.readback,  s.total};
        for (int i = 0; i < 8; ++i) t[i].push_back(values[i]);
      }
      const char* label = !surface_only ? "image+depth" : with_image ? "image+depth,s" : "depth,s";
      std::printf("%9d %-13s %9zu", count, label, out.particles_in_depth);
      for (const auto& series : t) std::printf("  %5.1f / %5.1f", mean(series), median(series));
      // Busy time of all threads per frame: on an idle 2-core machine a frame takes at
      // least half of it, whatever else the machine is doing now.
      std::printf("  %8.1f\n", (processCpuMilliseconds() - cpu_start) / o.frames);
      if (!o.png_dir.empty() && with_image) {
        const std::string stem = o.png_dir + "/bench_" + std::to_string(count) + "_" + o.filter +
                                 (surface_only ? "_surface" : "");
        pbf::writePng(stem + "_image.png", out.width, out.height, 4, out.rgba);
        pbf::writePng(stem + "_depth.png", out.width, out.height, 4, pbf::depthToRgba(out.depth));
      }
    }
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "pbf_render_bench: " << e.what() << "\n";
    return 1;
  }
}
