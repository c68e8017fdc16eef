// `fibrodem bench` runs in the bench module (modules/bench), with Google
// Benchmark and its own copy of the core, opened by that command alone so
// that no other command loads libbenchmark (docs/topics/performance.md#start-up).
#pragma once

#include <string>
#include <vector>

namespace fibrodem::cli {

// The module's entry point: runs the suites with benchmark's own options
// (`args`); returns the command's exit status.
inline constexpr const char* kBenchEntry = "fibrodem_bench_v1";
using BenchEntry = int (*)(const char* program, const std::vector<std::string>* args);

}  // namespace fibrodem::cli
