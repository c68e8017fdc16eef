#include "apps/bench_module.hpp"
#include "apps/commands.hpp"
#include "util/runtime_module.hpp"

namespace fibrodem::cli {

int bench_command(const char* program, const std::vector<std::string>& args) {
  const auto entry = reinterpret_cast<BenchEntry>(module_entry("bench", kBenchEntry, "needed by `fibrodem bench`"));
  return entry(program, &args);
}

}  // namespace fibrodem::cli
