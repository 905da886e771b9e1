#include "NeighborSums.h"

// Chooses, once, the build of the neighbour sums this CPU runs. Static initialisation would
// race with other libraries' start-up code; a function-local static is initialised on first
// use, thread-safely.

namespace pbf {

namespace {

struct NeighborSumsTable {
  decltype(&neighbor_sums_base::lambdaSums) lambda;
  decltype(&neighbor_sums_base::deltaSums) delta;
  decltype(&neighbor_sums_base::densitySums) density;
  decltype(&neighbor_sums_base::xsphSums) xsph;
  decltype(&neighbor_sums_base::lambdaSumsWithImages) lambda_with_images;
  decltype(&neighbor_sums_base::deltaSumsWithImage) delta_with_image;
  decltype(&neighbor_sums_base::imageLambdaSums) image_lambda;
  decltype(&neighbor_sums_base::imageDeltaSums) image_delta;
  decltype(&neighbor_sums_base::imageDensitySums) image_density;
  decltype(&neighbor_sums_base::readsPacked) reads_packed;
  const char* name;
};

bool cpuRunsV3() {
#if defined(__x86_64__) && defined(__GNUC__)
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma") &&
         __builtin_cpu_supports("bmi2");
#else
  return false;
#endif
}

const NeighborSumsTable& table() {
  static const NeighborSumsTable t =
      cpuRunsV3() ? NeighborSumsTable{neighbor_sums_v3::lambdaSums, neighbor_sums_v3::deltaSums,
                                      neighbor_sums_v3::densitySums, neighbor_sums_v3::xsphSums,
                                      neighbor_sums_v3::lambdaSumsWithImages,
                                      neighbor_sums_v3::deltaSumsWithImage,
                                      neighbor_sums_v3::imageLambdaSums, neighbor_sums_v3::imageDeltaSums,
                                      neighbor_sums_v3::imageDensitySums, neighbor_sums_v3::readsPacked,
                                      "x86-64-v3"}
                  : NeighborSumsTable{neighbor_sums_base::lambdaSums, neighbor_sums_base::deltaSums,
                                      neighbor_sums_base::densitySums, neighbor_sums_base::xsphSums,
                                      neighbor_sums_base::lambdaSumsWithImages,
                                      neighbor_sums_base::deltaSumsWithImage,
                                      neighbor_sums_base::imageLambdaSums,
                                      neighbor_sums_base::imageDeltaSums,
                                      neighbor_sums_base::imageDensitySums,
                                      neighbor_sums_base::readsPacked, "build target"};
  return t;
}

}  // namespace

LambdaSums lambdaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                      float* pair_gradient) {
  return table().lambda(a, k, i, pair_gradient);
}

VectorSum deltaSums(const NeighborArrays& a, std::size_t i, const float* lambda,
                    const float* pair_gradient) {
  return table().delta(a, i, lambda, pair_gradient);
}

DensitySum densitySums(const NeighborArrays& a, const PairConstants& k, std::size_t i) {
  return table().density(a, k, i);
}

VectorSum xsphSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                   const float* velocity, const float* density, const float* velocity_slots) {
  return table().xsph(a, k, i, velocity, density, velocity_slots);
}

LambdaSums lambdaSumsWithImages(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                                const Reflection* r, int count, float* pair_gradient,
                                float* image_gradient) {
  return table().lambda_with_images(a, k, i, r, count, pair_gradient, image_gradient);
}

VectorSum deltaSumsWithImage(const NeighborArrays& a, std::size_t i, const Reflection& r,
                             const float* lambda, const float* pair_gradient,
                             const float* image_gradient) {
  return table().delta_with_image(a, i, r, lambda, pair_gradient, image_gradient);
}

LambdaSums imageLambdaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                           const Reflection& r) {
  return table().image_lambda(a, k, i, r);
}

VectorSum imageDeltaSums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                         const Reflection& r, const float* lambda) {
  return table().image_delta(a, k, i, r, lambda);
}

DensitySum imageDensitySums(const NeighborArrays& a, const PairConstants& k, std::size_t i,
                            const Reflection& r) {
  return table().image_density(a, k, i, r);
}

const char* neighborSumsVariant() { return table().name; }

bool neighborSumsReadPacked() { return table().reads_packed(); }

}  // namespace pbf
