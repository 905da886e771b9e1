#pragma once
// A parallel sum whose result does not depend on the thread count.

#include <algorithm>
#include <cstddef>
#include <vector>

namespace pbf {

// Sum of f(i) over [0, n) in a fixed association order: chunks of fixed size summed in
// parallel, then the chunk sums in order. Results are bitwise identical for any thread
// count, which keeps tolerance-driven iteration counts independent of the threads.
constexpr std::size_t kDeterministicSumChunk = 2048;

template <typename F>
inline double deterministicSum(std::size_t n, F f) {
  constexpr std::size_t kChunk = kDeterministicSumChunk;
  const std::size_t chunks = (n + kChunk - 1) / kChunk;
  // Kept between calls: no allocation per call. The reference, taken here, is the calling
  // thread's vector; inside the loop `kept` would name each worker's own.
  thread_local std::vector<double> kept;
  std::vector<double>& partial = kept;
  partial.assign(chunks, 0.0);
#pragma omp parallel for schedule(static)
  for (std::size_t c = 0; c < chunks; ++c) {
    double s = 0.0;
    const std::size_t end = std::min(n, (c + 1) * kChunk);
    for (std::size_t i = c * kChunk; i < end; ++i) s += f(i);
    partial[c] = s;
  }
  double total = 0.0;
  for (double s : partial) total += s;
  return total;
}

}  // namespace pbf
