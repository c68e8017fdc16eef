// The subcommands of `fibrodem`, one function each. Exit codes: 0 success,
// 2 bad manifest, 3 plugin problem, 4 the run failed (outputs so far kept).
#pragma once

#include <iostream>
#include <string>
#include <vector>

#include "model/plugin_registry.hpp"
#include "scene/manifest_error.hpp"

namespace fibrodem::cli {

struct RunArgs {
  std::string manifest;
  std::string out;
  std::vector<std::string> overrides;
  bool quiet = false;
};

struct CompareArgs {
  std::vector<std::string> manifests;  // one or two
  std::string out;
  std::vector<std::string> overrides, a_overrides, b_overrides;
  bool quiet = false;
};

struct SweepArgs {
  std::string sweep;
  std::string out;
  unsigned jobs = 0;  // 0: one per core
};

int run_command(const RunArgs& args);
int sweep_command(const SweepArgs& args);
int compare_command(const CompareArgs& args);
int validate_command(const RunArgs& args);
int plugins_command(bool as_json);
int bench_command(const char* program, const std::vector<std::string>& args);

// Runs `body`, turning each kind of failure into a message and an exit code.
template <class Body>
int guarded(Body body) {
  try {
    return body();
  } catch (const ManifestError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  } catch (const PluginError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 4;
  }
}

}  // namespace fibrodem::cli
