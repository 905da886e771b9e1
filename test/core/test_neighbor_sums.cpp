// The solver's neighbour sums (src/core/NeighborSums.h), both builds: the portable loops and,
// where the CPU has AVX2, the hand-written wide ones (WideNeighborSums.h), each against the
// equations evaluated in double precision. Lists of every length from 0 to 45 cover each
// count of neighbours in the last, masked group; they hold pairs beyond h (the lists' skin),
// a coincident pair, and, in one test, a NaN. The wide build is run with the positions
// gathered and with them in packed 16-byte slots (NeighborArrays::packed; XSPH's velocity
// slots).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <iostream>
#include <random>
#include <vector>

#include "NeighborSums.h"

namespace {

constexpr float kH = 0.04f;
constexpr double kPi = 3.14159265358979323846;

// The kernel constants the passes use (Kernels.h: Spiky density and gradient, Poly6 for XSPH),
// with a mass and rest density of the shipped order.
pbf::PairConstants constants() {
  const double h = kH, mass = 0.008, rho0 = 1000.0;
  pbf::PairConstants k;
  k.h = kH;
  k.h2 = kH * kH;
  k.poly6 = static_cast<float>(mass * 315.0 / (64.0 * kPi * std::pow(h, 9)));
  k.density = static_cast<float>(mass * 15.0 / (kPi * std::pow(h, 6)));
  k.spiky = static_cast<float>(mass / rho0 * 45.0 / (kPi * std::pow(h, 6)));
  k.coincident2 = 1e-12f * k.h2;
  return k;
}

// Particle 0 with `count` neighbours (particles 1..count) scattered up to 1.3 h away;
// neighbour 2, if any, sits on particle 0 (a coincident pair).
struct Cloud {
  Cloud(std::size_t count, std::mt19937& rng) {
    std::uniform_real_distribution<float> u(-1.3f * kH, 1.3f * kH), v(-1.0f, 1.0f), d(900.0f, 1100.0f);
    position = {0.011f, -0.007f, 0.013f};
    for (std::size_t j = 1; j <= count; ++j) {
      const float x = j == 2 ? 0.0f : u(rng), y = j == 2 ? 0.0f : u(rng), z = j == 2 ? 0.0f : u(rng);
      position.insert(position.end(), {position[0] + x, position[1] + y, position[2] + z});
    }
    for (std::size_t j = 0; j <= count; ++j) {
      velocity.insert(velocity.end(), {v(rng), v(rng), v(rng)});
      lambda.push_back(-1e-6f * (1.0f + v(rng)));
      density.push_back(d(rng));
    }
    // Particle 0's list starts at an offset that is not a multiple of the group width.
    offset = {3, static_cast<std::uint32_t>(3 + count)};
    index.assign(3, 0);
    for (std::size_t j = 1; j <= count; ++j) index.push_back(static_cast<std::uint32_t>(j));
  }
  // With `packed`, also the 16-byte slots (x, y, z, lambda) the wide build loads neighbours
  // from instead of gathering, as the solver's lambda pass fills them for the delta-p pass.
  // Also the velocity slots (vx, vy, vz, density) for XSPH.
  pbf::NeighborArrays arrays(bool packed = false) {
    slots.clear();
    velocity_slots.clear();
    for (std::size_t j = 0; j < position.size() / 3; ++j) {
      slots.insert(slots.end(), {position[3 * j], position[3 * j + 1], position[3 * j + 2], lambda[j]});
      velocity_slots.insert(velocity_slots.end(),
                            {velocity[3 * j], velocity[3 * j + 1], velocity[3 * j + 2], density[j]});
    }
    return {position.data(), offset.data(), index.data(), packed ? slots.data() : nullptr};
  }
  std::vector<float> position, velocity, lambda, density, slots, velocity_slots;
  std::vector<std::uint32_t> offset, index;
};

// The floor z = 0: image of x is (x, y, -z).
pbf::Reflection floorMirror() {
  pbf::Reflection r{{1, 0, 0, 0, 1, 0, 0, 0, -1}, {0, 0, 0}, 1 << 4};
  return r;
}

struct Vec {
  double x = 0, y = 0, z = 0;
};

// One pair in double: d = x_i - x_j, r^2, (h - r)_+ and the Spiky gradient factor g
// (grad = g d; 0 for a coincident pair).
struct ReferencePair {
  ReferencePair(const Vec& pi, const Vec& pj, const pbf::PairConstants& k)
      : d{pi.x - pj.x, pi.y - pj.y, pi.z - pj.z}, r2(d.x * d.x + d.y * d.y + d.z * d.z) {
    const double r = std::sqrt(r2);
    dl = std::max(k.h - r, 0.0);
    g = r2 > k.coincident2 ? k.spiky * dl * dl / r : 0.0;
  }
  Vec d;
  double r2, dl, g;
};

// Reference lambda sums of particle 0 in double, with the images of its neighbours if
// `mirror` (one reflection); gradient factors per list entry as the passes cache them.
struct ReferenceLambda {
  ReferenceLambda(const Cloud& c, const pbf::PairConstants& k, bool mirror) {
    const double h = k.h;
    auto at = [&](std::size_t j) { return Vec{c.position[3 * j], c.position[3 * j + 1], c.position[3 * j + 2]}; };
    const Vec pi = at(0);
    for (std::uint32_t e = c.offset[0]; e < c.offset[1]; ++e) {
      const Vec pj = at(c.index[e]);
      const ReferencePair p(pi, pj, k);
      const Vec& d = p.d;
      const double g = p.g;
      rho += k.density * p.dl * p.dl * p.dl;
      within += p.r2 < static_cast<double>(k.h2) ? 1 : 0;
      coincident += p.r2 > k.coincident2 ? 0 : 1;
      gradient.push_back(g);
      Vec v{g * d.x, g * d.y, g * d.z};
      double gi = 0.0;
      if (mirror) {
        const Vec e2{pi.x - pj.x, pi.y - pj.y, pi.z + pj.z};  // x_i - image of j
        const double s2 = e2.x * e2.x + e2.y * e2.y + e2.z * e2.z, s = std::sqrt(s2);
        const double sl = std::max(h - s, 0.0);
        rho += k.density * sl * sl * sl;
        if (s2 > k.coincident2) gi = k.spiky * sl * sl / s;
        grad.x += gi * e2.x, grad.y += gi * e2.y, grad.z += gi * e2.z;
        // grad_j C_i also holds the image pair: R x_i - x_j
        v.x += gi * (pi.x - pj.x), v.y += gi * (pi.y - pj.y), v.z += gi * (-pi.z - pj.z);
      }
      image_gradient.push_back(gi);
      grad.x += g * d.x, grad.y += g * d.y, grad.z += g * d.z;
      sum_grad2 += v.x * v.x + v.y * v.y + v.z * v.z;
    }
  }
  double rho = 0, sum_grad2 = 0;
  Vec grad;
  int coincident = 0;
  std::uint32_t within = 0;
  std::vector<double> gradient, image_gradient;
};

// |a - b| within a relative tolerance of `scale` (the size of the sum's terms: float
// accumulation of up to 45 of them).
void expectNear(double a, double b, double scale, const char* what, std::size_t count) {
  EXPECT_NEAR(a, b, 2e-5 * scale + 1e-30) << what << ", " << count << " neighbours ("
                                          << pbf::neighborSumsVariant() << " CPU)";
}

bool cpuHasAvx2() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

template <typename F>
void forEachBuild(F f) {
  f(pbf::neighbor_sums_base::lambdaSums, pbf::neighbor_sums_base::deltaSums,
    pbf::neighbor_sums_base::densitySums, pbf::neighbor_sums_base::xsphSums,
    pbf::neighbor_sums_base::lambdaSumsWithImages, pbf::neighbor_sums_base::deltaSumsWithImage,
    pbf::neighbor_sums_base::imageDensitySums, "portable");
  if (!cpuHasAvx2()) {  // the portable loops are what this CPU runs
    std::cout << "no AVX2 on this CPU: the wide neighbour sums are not tested here\n";
    return;
  }
  f(pbf::neighbor_sums_v3::lambdaSums, pbf::neighbor_sums_v3::deltaSums,
    pbf::neighbor_sums_v3::densitySums, pbf::neighbor_sums_v3::xsphSums,
    pbf::neighbor_sums_v3::lambdaSumsWithImages, pbf::neighbor_sums_v3::deltaSumsWithImage,
    pbf::neighbor_sums_v3::imageDensitySums, "AVX2");
}

}  // namespace

TEST(NeighborSums, BothBuildsAgreeWithTheEquations) {
  const pbf::PairConstants k = constants();
  const double rho_scale = k.density * std::pow(kH, 3) * 45, grad_scale = k.spiky * kH * kH * 45;
  forEachBuild([&](auto lambda_sums, auto delta_sums, auto density_sums, auto xsph_sums,
                   auto lambda_sums_images, auto delta_sums_image, auto image_density_sums,
                   const char* build) {
    SCOPED_TRACE(build);
    std::mt19937 rng(5);
    for (std::size_t count = 0; count <= 45; ++count) {
      Cloud c(count, rng);
      for (bool packed : {false, true}) {
        SCOPED_TRACE(packed ? "packed slots" : "gathered positions");
        const pbf::NeighborArrays a = c.arrays(packed);
        for (bool mirror : {false, true}) {
          SCOPED_TRACE(mirror ? "with the floor's images" : "direct pairs");
          const ReferenceLambda ref(c, k, mirror);
          // Laid out like the lists; the sums take particle 0's rows (NeighborSums.h).
          std::vector<float> g(c.index.size() + 8, -1.0f), gi(g.size(), -1.0f);
          float* const row = g.data() + c.offset[0];
          float* const image_row = gi.data() + c.offset[0];
          const pbf::Reflection r = floorMirror();
          const pbf::LambdaSums s = mirror ? lambda_sums_images(a, k, 0, &r, 1, row, image_row)
                                           : lambda_sums(a, k, 0, row);
          expectNear(s.rho, ref.rho, rho_scale, "density", count);
          expectNear(s.gx, ref.grad.x, grad_scale, "gradient x", count);
          expectNear(s.gy, ref.grad.y, grad_scale, "gradient y", count);
          expectNear(s.gz, ref.grad.z, grad_scale, "gradient z", count);
          expectNear(s.sum_grad2, ref.sum_grad2, grad_scale * grad_scale, "sum of squared gradients", count);
          EXPECT_EQ(s.coincident, ref.coincident) << count;
          EXPECT_EQ(s.within, ref.within) << count;
          for (std::size_t e = 0; e < g.size(); ++e) {
            const bool listed = e >= c.offset[0] && e < c.offset[1];
            if (!listed) {  // the masked group writes nothing outside the list
              EXPECT_EQ(g[e], -1.0f) << "entry " << e << " of " << count;
              if (mirror) {
                EXPECT_EQ(gi[e], -1.0f) << "entry " << e << " of " << count;
              }
              continue;
            }
            const double scale = k.spiky * kH;
            expectNear(g[e], ref.gradient[e - c.offset[0]], scale, "pair gradient", count);
            if (mirror) {
              expectNear(gi[e], ref.image_gradient[e - c.offset[0]], scale, "image gradient", count);
            }
          }

          // delta p: sum_j (lambda_i + lambda_j) g_ij (x_i - x_j) [+ images]
          Vec dp;
          for (std::uint32_t e = c.offset[0]; e < c.offset[1]; ++e) {
            const std::uint32_t j = c.index[e];
            const double lij = static_cast<double>(c.lambda[0]) + c.lambda[j];
            const double dx = c.position[0] - c.position[3 * j], dy = c.position[1] - c.position[3 * j + 1],
                         dz = c.position[2] - c.position[3 * j + 2];
            const double gg = lij * g[e], gm = mirror ? lij * gi[e] : 0.0;
            dp.x += gg * dx + gm * dx;
            dp.y += gg * dy + gm * dy;
            dp.z += gg * dz + gm * (c.position[2] + c.position[3 * j + 2]);
          }
          const pbf::VectorSum d = mirror ? delta_sums_image(a, 0, r, c.lambda.data(), row, image_row)
                                          : delta_sums(a, 0, c.lambda.data(), row);
          const double dp_scale = 2e-6 * k.spiky * kH * kH * 45;
          expectNear(d.x, dp.x, dp_scale, "delta p x", count);
          expectNear(d.y, dp.y, dp_scale, "delta p y", count);
          expectNear(d.z, dp.z, dp_scale, "delta p z", count);
        }

        // Density and neighbour count, directly and of the floor's images; XSPH.
        double rho = 0.0, image_rho = 0.0;
        std::uint32_t within = 0, images_within = 0;
        Vec xsph;
        for (std::uint32_t e = c.offset[0]; e < c.offset[1]; ++e) {
          const std::uint32_t j = c.index[e];
          const double dx = c.position[0] - c.position[3 * j], dy = c.position[1] - c.position[3 * j + 1],
                       dz = c.position[2] - c.position[3 * j + 2];
          const double r2 = dx * dx + dy * dy + dz * dz, dl = std::max(kH - std::sqrt(r2), 0.0);
          rho += k.density * dl * dl * dl;
          within += r2 < static_cast<double>(k.h2) ? 1 : 0;
          const double iz = c.position[2] + c.position[3 * j + 2];  // x_i - image of j
          const double s2 = dx * dx + dy * dy + iz * iz, sl = std::max(kH - std::sqrt(s2), 0.0);
          image_rho += k.density * sl * sl * sl;
          images_within += s2 < static_cast<double>(k.h2) ? 1 : 0;
          const double w = std::max(static_cast<double>(k.h2) - r2, 0.0);
          const double f = k.poly6 * w * w * w / c.density[j];
          xsph.x += f * (c.velocity[3 * j] - c.velocity[0]);
          xsph.y += f * (c.velocity[3 * j + 1] - c.velocity[1]);
          xsph.z += f * (c.velocity[3 * j + 2] - c.velocity[2]);
        }
        const pbf::DensitySum ds = density_sums(a, k, 0);
        expectNear(ds.rho, rho, rho_scale, "density pass", count);
        EXPECT_EQ(ds.count, within) << count;
        const pbf::DensitySum is = image_density_sums(a, k, 0, floorMirror());
        expectNear(is.rho, image_rho, rho_scale, "density pass, images", count);
        EXPECT_EQ(is.count, images_within) << count;
        const pbf::VectorSum xs = xsph_sums(a, k, 0, c.velocity.data(), c.density.data(),
                                            packed ? c.velocity_slots.data() : nullptr);
        const double xsph_scale = k.poly6 * std::pow(kH, 6) / 900.0 * 2.0 * 45;
        expectNear(xs.x, xsph.x, xsph_scale, "XSPH x", count);
        expectNear(xs.y, xsph.y, xsph_scale, "XSPH y", count);
        expectNear(xs.z, xsph.z, xsph_scale, "XSPH z", count);
      }
    }
  });
}

// A NaN position must reach the density (the step's guard rejects the step on it), in either
// build, wherever in the list the NaN neighbour sits.
TEST(NeighborSums, ANaNNeighbourMakesTheDensityNaN) {
  const pbf::PairConstants k = constants();
  forEachBuild([&](auto lambda_sums, auto, auto density_sums, auto, auto lambda_sums_images, auto,
                   auto image_density_sums, const char* build) {
    SCOPED_TRACE(build);
    std::mt19937 rng(9);
    for (std::size_t count = 1; count <= 17; ++count) {
      Cloud c(count, rng);
      c.position[3 * count + 1] = std::nanf("");
      std::vector<float> g(c.index.size() + 8), gi(g.size());
      const pbf::Reflection r = floorMirror();
      for (bool packed : {false, true}) {
        EXPECT_TRUE(std::isnan(lambda_sums(c.arrays(packed), k, 0, g.data()).rho)) << count;
        EXPECT_TRUE(std::isnan(lambda_sums_images(c.arrays(packed), k, 0, &r, 1, g.data(), gi.data()).rho)) << count;
        EXPECT_TRUE(std::isnan(density_sums(c.arrays(packed), k, 0).rho)) << count;
        EXPECT_TRUE(std::isnan(image_density_sums(c.arrays(packed), k, 0, r).rho)) << count;
      }
    }
  });
}

namespace {

// A mirror across the plane x_axis = 0: image of x has that coordinate negated.
pbf::Reflection axisMirror(int axis) {
  pbf::Reflection r{{1, 0, 0, 0, 1, 0, 0, 0, 1}, {0, 0, 0}, 1 << (2 * axis)};
  r.m[4 * axis] = -1;
  return r;
}

// The product of two mirrors (the image across an edge's two walls).
pbf::Reflection bothMirrors(int a, int b) {
  pbf::Reflection r = axisMirror(a);
  r.m[4 * b] = -1;
  r.walls |= 1 << (2 * b);
  return r;
}

Vec image(const pbf::Reflection& r, const Vec& x) {
  return {r.m[0] * x.x + r.m[1] * x.y + r.m[2] * x.z + r.b[0], r.m[3] * x.x + r.m[4] * x.y + r.m[5] * x.z + r.b[1],
          r.m[6] * x.x + r.m[7] * x.y + r.m[8] * x.z + r.b[2]};
}

}  // namespace

// Particles at an edge or a corner (several reflections; the scalar loop's semantics:
// images beyond h or on top of particle i add nothing), and the images' delta p of one
// reflection with the gradients recomputed.
TEST(NeighborSums, EdgesAndCornersAgreeWithTheEquations) {
  const pbf::PairConstants k = constants();
  const double rho_scale = k.density * std::pow(kH, 3) * 45, grad_scale = k.spiky * kH * kH * 45;
  const std::vector<pbf::Reflection> edge = {axisMirror(0), axisMirror(2), bothMirrors(0, 2)};
  struct Build {
    decltype(&pbf::neighbor_sums_base::lambdaSumsWithImages) lambda_images;
    decltype(&pbf::neighbor_sums_base::imageDeltaSums) image_delta;
    const char* name;
  };
  std::vector<Build> builds = {{pbf::neighbor_sums_base::lambdaSumsWithImages,
                                pbf::neighbor_sums_base::imageDeltaSums, "portable"}};
  if (cpuHasAvx2())
    builds.push_back({pbf::neighbor_sums_v3::lambdaSumsWithImages, pbf::neighbor_sums_v3::imageDeltaSums, "AVX2"});
  for (const Build& b : builds) {
    SCOPED_TRACE(b.name);
    std::mt19937 rng(13);
    for (std::size_t count = 0; count <= 45; ++count) {
      Cloud c(count, rng);
      for (bool packed : {false, true}) {
        SCOPED_TRACE(packed ? "packed slots" : "gathered positions");
        auto at = [&](std::size_t j) { return Vec{c.position[3 * j], c.position[3 * j + 1], c.position[3 * j + 2]}; };
        const Vec pi = at(0);
        for (int reflections : {2, 3}) {
          SCOPED_TRACE(reflections);
          double rho = 0, sum_grad2 = 0;
          Vec grad;
          for (std::uint32_t e = c.offset[0]; e < c.offset[1]; ++e) {
            const Vec pj = at(c.index[e]);
            const ReferencePair p(pi, pj, k);
            rho += k.density * p.dl * p.dl * p.dl;
            Vec v{p.g * p.d.x, p.g * p.d.y, p.g * p.d.z};
            grad.x += v.x, grad.y += v.y, grad.z += v.z;
            for (int q = 0; q < reflections; ++q) {
              const Vec im = image(edge[q], pj), ri = image(edge[q], pi);
              const Vec s{pi.x - im.x, pi.y - im.y, pi.z - im.z};
              const double s2 = s.x * s.x + s.y * s.y + s.z * s.z;
              if (s2 >= static_cast<double>(k.h2) || s2 <= k.coincident2) continue;
              const double sl = kH - std::sqrt(s2), gi = k.spiky * sl * sl / std::sqrt(s2);
              rho += k.density * sl * sl * sl;
              grad.x += gi * s.x, grad.y += gi * s.y, grad.z += gi * s.z;
              v.x += gi * (ri.x - pj.x), v.y += gi * (ri.y - pj.y), v.z += gi * (ri.z - pj.z);
            }
            sum_grad2 += v.x * v.x + v.y * v.y + v.z * v.z;
          }
          std::vector<float> g(c.index.size() + 8, -1.0f), unused(g.size(), -1.0f);
          const pbf::LambdaSums s = b.lambda_images(c.arrays(packed), k, 0, edge.data(), reflections,
                                                    g.data() + c.offset[0], unused.data() + c.offset[0]);
          expectNear(s.rho, rho, rho_scale, "density", count);
          expectNear(s.gx, grad.x, grad_scale, "gradient x", count);
          expectNear(s.gy, grad.y, grad_scale, "gradient y", count);
          expectNear(s.gz, grad.z, grad_scale, "gradient z", count);
          expectNear(s.sum_grad2, sum_grad2, grad_scale * grad_scale, "sum of squared gradients", count);
        }
        // The images' delta p under the edge's double reflection.
        Vec dp;
        for (std::uint32_t e = c.offset[0]; e < c.offset[1]; ++e) {
          const std::uint32_t j = c.index[e];
          const Vec im = image(edge[2], at(j));
          const Vec s{pi.x - im.x, pi.y - im.y, pi.z - im.z};
          const double s2 = s.x * s.x + s.y * s.y + s.z * s.z, len = std::sqrt(s2);
          if (s2 <= k.coincident2) continue;
          const double sl = std::max(kH - len, 0.0);
          const double f = (static_cast<double>(c.lambda[0]) + c.lambda[j]) * k.spiky * sl * sl / len;
          dp.x += f * s.x, dp.y += f * s.y, dp.z += f * s.z;
        }
        const pbf::VectorSum d = b.image_delta(c.arrays(packed), k, 0, edge[2], c.lambda.data());
        const double dp_scale = 2e-6 * grad_scale;
        expectNear(d.x, dp.x, dp_scale, "image delta p x", count);
        expectNear(d.y, dp.y, dp_scale, "image delta p y", count);
        expectNear(d.z, dp.z, dp_scale, "image delta p z", count);
      }
    }
  }
}
