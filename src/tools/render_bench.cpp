// pbf_render_bench: milliseconds per render pass for dam-break-like blocks of particles.
// No ROS. Each frame renders image + depth (what the node publishes) at 640x480 by
// default; the first frames are a warm-up (shader JIT, allocation) and are not counted.
//
//   pbf_render_bench [--backend osmesa|egl] [--frames N] [--warmup N] [--width W]
//                    [--height H] [--filter narrow|bilateral|none] [--counts 20000,80000]
//                    [--shaders DIR] [--png DIR]

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <random>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "pbf_ros/render/FluidRenderer.h"
#include "pbf_ros/render/ImageWriter.h"

namespace {

struct Options {
  std::string backend = "osmesa";
  int frames = 30, warmup = 5, width = 640, height = 480;
  std::string filter = "narrow";
  std::vector<int> counts = {20000, 80000};
  std::string shader_dir = PBF_SHADER_SOURCE_DIR;
  std::string png_dir;
};

Options parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      return argv[++i];
    };
    if (arg == "--backend") o.backend = value();
    else if (arg == "--frames") o.frames = std::stoi(value());
    else if (arg == "--warmup") o.warmup = std::stoi(value());
    else if (arg == "--width") o.width = std::stoi(value());
    else if (arg == "--height") o.height = std::stoi(value());
    else if (arg == "--filter") o.filter = value();
    else if (arg == "--shaders") o.shader_dir = value();
    else if (arg == "--png") o.png_dir = value();
    else if (arg == "--counts") {
      o.counts.clear();
      std::stringstream list(value());
      for (std::string item; std::getline(list, item, ',');) o.counts.push_back(std::stoi(item));
    } else {
      throw std::invalid_argument("unknown argument " + arg +
                                  " (see the comment at the top of render_bench.cpp)");
    }
  }
  if (o.frames < 1) throw std::invalid_argument("--frames must be at least 1");
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

    pbf::FluidRenderer renderer(pbf::createGlBackend(o.backend), o.shader_dir, render_options);
    std::printf("backend %s: %s\n", o.backend.c_str(), renderer.glDescription().c_str());

    const float spacing = 0.01f, radius = 0.5f * spacing;
    pbf::RenderCamera camera;
    camera.width = o.width;
    camera.height = o.height;
    camera.camera_to_world =
        pbf::lookAt(Eigen::Vector3f(1.05f, -0.55f, 0.55f), Eigen::Vector3f(0.32f, 0.22f, 0.05f));
    pbf::RenderRequest request;  // image + depth: what the node publishes

    std::printf("%dx%d, filter %s, %d frames after %d warm-up, ms per pass (mean / median)\n",
                o.width, o.height, o.filter.c_str(), o.frames, o.warmup);
    std::printf("%9s %9s %13s %13s %13s %13s %13s %13s %13s %13s\n", "particles", "in view",
                "cull+upload", "depth", "thickness", "filter", "normals", "composite",
                "readback", "total");
    for (int count : o.counts) {
      const std::vector<Eigen::Vector3f> particles = damBreakBlock(count, spacing);
      pbf::RenderOutput out;
      std::vector<double> t[8];
      for (int frame = 0; frame < o.warmup + o.frames; ++frame) {
        renderer.render(particles, radius, camera, request, out);
        if (frame < o.warmup) continue;
        const pbf::RenderTimings& s = out.timings;
        const double values[8] = {s.cull_upload, s.depth,     s.thickness, s.filter,
                                  s.normals,     s.composite, s.readback,  s.total};
        for (int i = 0; i < 8; ++i) t[i].push_back(values[i]);
      }
      std::printf("%9d %9zu", count, out.particles_in_view);
      for (const auto& series : t) std::printf("  %5.1f / %5.1f", mean(series), median(series));
      std::printf("\n");
      if (!o.png_dir.empty()) {
        const std::string stem = o.png_dir + "/bench_" + std::to_string(count) + "_" + o.filter;
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
