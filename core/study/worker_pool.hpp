// Independent runs of a study on a pool of worker threads: items 0..n-1 in
// any order, `jobs` at a time (0: one per core), each followed by `done`
// (if given) under a lock, so that progress reports do not interleave.
#pragma once

#include <cstddef>
#include <functional>

namespace fibrodem {

void for_each_in_parallel(std::size_t n, unsigned jobs, const std::function<void(std::size_t)>& work,
                          const std::function<void(std::size_t)>& done = {});

}  // namespace fibrodem
