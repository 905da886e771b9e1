#pragma once
// The neighbour sums of the solver's hot passes, over raw float arrays (positions and
// velocities as packed x,y,z triples, CSR neighbour lists). Each is built twice, for
// x86-64-v3 (AVX2 + FMA) and for the build's target (plain x86-64 by default), and the
// first call picks the one the CPU runs (NeighborSumsDispatch.cpp): a portable binary still
// uses the wide registers where they exist. (GCC's target_clones would be simpler, but it
// drops the `omp simd` vectorisation in the AVX2 clone.)
// Private to pbf_core; the passes in ConstraintPasses.cpp / VelocityPasses.cpp call them
// once per particle and do the rare and per-particle work (coincident pairs, walls).

#include <cstddef>
#include <cstdint>

namespace pbf {

// CSR neighbour lists and the packed positions they index.
struct NeighborArrays {
  const float* position;       // x,y,z per particle
  const std::uint32_t* offset;  // n + 1 entries
  const std::uint32_t* index;
  // Optional: the same positions in 16-byte slots x, y, z, w (PackedSlots.h), with w
  // the particle's multiplier lambda for the delta-p sums (deltaSums, deltaSumsWithImage,
  // imageDeltaSums: their `lambda` array is then not read) and unused by the others. The
  // x86-64-v3 build loads neighbours (and i itself) from these slots instead of gathering
  // each coordinate, so they must hold the current positions; the portable build ignores
  // them.
  const float* packed = nullptr;
};

// Kernel constants of one pass, premultiplied by the mass / volume factors it needs.
struct PairConstants {
  float h, h2;
  float poly6;       // m * Poly6 coefficient: m W(r) = poly6 * (h^2 - r^2)^3 (XSPH)
  float density;     // m * Spiky coefficient: m W(r) = density * (h - r)^3 (Kernels.h)
  float spiky;       // (m / rho0) * Spiky gradient coefficient
  float coincident2; // pairs with r^2 at or below this have no direction
};

// Per-pair values (pair_gradient, image_gradient below) are rows of particle i's list: the
// value of its k-th neighbour, entry offset[i] + k of the list, is at row[k]. The Jacobi
// passes keep one row per particle in an array laid out like the lists (row = array +
// offset[i]), to use in the delta-p pass; the Gauss-Seidel sweep needs them only within one
// projection and reuses one row per thread.

// Density, constraint gradient sum and sum of squared gradients of particle i (the lambda
// pass, eq 8-9). Writes each pair's gradient factor g (grad = g * r) to pair_gradient (i's
// row) for the delta-p pass. `coincident` counts pairs without a direction (left out of the sums),
// `within` the neighbours closer than h (images not counted), as densitySums does.
struct LambdaSums {
  float rho, gx, gy, gz, sum_grad2;
  int coincident;
  std::uint32_t within;
};
LambdaSums lambdaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                      float* pair_gradient);

// sum_j (lambda_i + lambda_j) g_ij r_ij: particle i's position correction (eq 12, no
// s_corr), from the lambda pass's pair factors (0 for coincident pairs, which the lambda
// pass counted: the caller redoes them).
struct VectorSum {
  float x, y, z;
};
VectorSum deltaSums(const NeighborArrays& a, std::size_t i, const float* lambda,
                    const float* pair_gradient);

// Density (m W summed over neighbours within h, self excluded) and that neighbour count.
struct DensitySum {
  float rho;
  std::uint32_t count;
};
DensitySum densitySums(const NeighborArrays& a, const PairConstants& k, std::size_t i);

// XSPH sum_j (m / rho_j) W_ij (v_j - v_i) of particle i (eq 10); `velocity` packed like
// positions. k.poly6 must be the bare mass times the Poly6 coefficient. `velocity_slots`
// (optional, with a.packed): the same velocities in 16-byte slots with the density in w,
// which the x86-64-v3 build then loads instead of gathering.
VectorSum xsphSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                   const float* velocity, const float* density,
                   const float* velocity_slots = nullptr);

// A mirror image map x -> m x + b (row-major 3x3, world frame) across one, two or three
// container walls (ContainerMirror.h); `walls` has bit f set for each face f reflected across.
struct Reflection {
  float m[9], b[3];
  int walls;
};

// lambdaSums with the images of i's neighbours under `count` reflections (i's own images are
// left to the caller). sum_grad2 is exact: grad_j C_i is the sum of j's own pair gradient
// and those of its images, squared after summing (summing the squares under-estimated it
// by up to a third at a wall, enough for single Jacobi iterations to overshoot).
// With one reflection (a particle by one wall, the common case) it also writes each image
// pair's gradient factor to image_gradient, for deltaSumsWithImage.
LambdaSums lambdaSumsWithImages(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                                const Reflection* r, int count, float* pair_gradient,
                                float* image_gradient);

// deltaSums plus the images' part under one reflection, sum_j (lambda_i + lambda_j)
// g'_ij (x_i - image_j), from the factors lambdaSumsWithImages cached (i's own image left to
// the caller): one pass over the neighbours for both.
VectorSum deltaSumsWithImage(const NeighborArrays& a, std::size_t i, const Reflection& r,
                             const float* lambda, const float* pair_gradient,
                             const float* image_gradient);

// lambdaSums over the images of i's neighbours under one reflection (i's own image is left
// to the caller): density, sum_j grad_i W(x_i - image_j), sum of squared gradients (of the
// images alone: the rare coincident-pair path).
LambdaSums imageLambdaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                           const Reflection& r);

// sum_j (lambda_i + lambda_j) grad W(x_i - image_j): the images' part of i's correction
// (i's own image left to the caller), gradients recomputed: for particles at an edge or a
// corner (several reflections), which are few.
VectorSum imageDeltaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                         const Reflection& r, const float* lambda);

// densitySums over the images of i's neighbours (count: images within h).
DensitySum imageDensitySums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                            const Reflection& r);

// Which build of the kernels runs: "x86-64-v3" or "build target".
const char* neighborSumsVariant();

// Whether the running build reads NeighborArrays::packed (the caller need not fill it if not).
bool neighborSumsReadPacked();

// The two builds (NeighborSums.cpp compiled twice); callers use the functions above.
#define PBF_DECLARE_NEIGHBOR_SUMS(ns)                                                          \
  namespace ns {                                                                              \
  LambdaSums lambdaSums(const NeighborArrays&, const PairConstants&, std::size_t, float*);    \
  VectorSum deltaSums(const NeighborArrays&, std::size_t, const float*, const float*);        \
  DensitySum densitySums(const NeighborArrays&, const PairConstants&, std::size_t);           \
  VectorSum xsphSums(const NeighborArrays&, const PairConstants&, std::size_t, const float*,   \
                     const float*, const float*);                                             \
  LambdaSums lambdaSumsWithImages(const NeighborArrays&, const PairConstants&, std::size_t,    \
                                  const Reflection*, int, float*, float*);                     \
  VectorSum deltaSumsWithImage(const NeighborArrays&, std::size_t, const Reflection&,          \
                               const float*, const float*, const float*);                      \
  LambdaSums imageLambdaSums(const NeighborArrays&, const PairConstants&, std::size_t,         \
                             const Reflection&);                                              \
  VectorSum imageDeltaSums(const NeighborArrays&, const PairConstants&, std::size_t,          \
                           const Reflection&, const float*);                                  \
  DensitySum imageDensitySums(const NeighborArrays&, const PairConstants&, std::size_t,       \
                              const Reflection&);                                             \
  bool readsPacked();                                                                         \
  }
PBF_DECLARE_NEIGHBOR_SUMS(neighbor_sums_base)
PBF_DECLARE_NEIGHBOR_SUMS(neighbor_sums_v3)
#undef PBF_DECLARE_NEIGHBOR_SUMS

}  // namespace pbf
