// The subcommands of `fibrodem`, one function each. Exit codes: 0 success,
// 2 bad manifest, 3 plugin problem, 4 the run failed (outputs so far kept).
#pragma once

#include <string>
#include <vector>

namespace fibrodem::cli {

struct RunArgs {
  std::string manifest;
  std::string out;
  std::vector<std::string> overrides;
  bool quiet = false;
};

int run_command(const RunArgs& args);
int validate_command(const RunArgs& args);
int plugins_command(bool as_json);
int bench_command(const char* program, const std::vector<std::string>& args);

}  // namespace fibrodem::cli
