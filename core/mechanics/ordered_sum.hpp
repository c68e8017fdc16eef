// Sums over many particles on all threads with the same bits for any number
// of threads: [0, n) is cut into a fixed number of parts (set by n alone), each
// part summed in index order, the parts' sums added in part order. (A plain
// OpenMP reduction adds the threads' sums in an order that depends on them.)
#pragma once

#include <array>
#include <cstddef>

namespace fibrodem {

// add_terms(i, acc) adds item i's K terms to acc (a std::array<double, K>).
template <std::size_t K, class AddTerms>
std::array<double, K> ordered_sum(std::size_t n, AddTerms add_terms) {
  constexpr std::size_t kParts = 64;
  std::array<std::array<double, K>, kParts> part{};
#pragma omp parallel for schedule(static)
  for (std::size_t k = 0; k < kParts; ++k) {
    // (A local sum stays in registers; part[k] itself could alias the
    // arrays summed, so each term would go through memory.)
    std::array<double, K> sum{};
    for (std::size_t i = n * k / kParts; i < n * (k + 1) / kParts; ++i) add_terms(i, sum);
    part[k] = sum;
  }
  std::array<double, K> total{};
  for (const auto& p : part)
    for (std::size_t j = 0; j < K; ++j) total[j] += p[j];
  return total;
}

}  // namespace fibrodem
