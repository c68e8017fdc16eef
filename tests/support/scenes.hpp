// Helpers shared by the test suites: manifests from literals, runs in memory.
#pragma once

#include <sys/wait.h>

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "run/simulation.hpp"
#include "tissue/tissue_builder.hpp"

namespace fibrodem::testing {

// A small valid manifest to start from; tests edit it.
inline json passive_cell_manifest() {
  return json::parse(R"({
    "fibrodem": 1, "name": "passive_cell", "duration_ms": 100,
    "tissue": {"builder": "single_cell", "type": "fibroblast"},
    "cells": {"fibroblast": {"model": "passive_fibroblast"}},
    "stimulus": [{"target": "fibroblast", "start_ms": 0, "duration_ms": 1000, "amplitude_pA": 1.0}],
    "solver": {"method": "euler", "dt_ms": 0.01},
    "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 1}}
  })");
}

inline std::string read_file(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// A CSV file's rows, each split at its commas (no quoting: fibrodem's CSV
// files have none); a trailing comma gives a last, empty cell.
inline std::vector<std::vector<std::string>> csv_rows(const std::filesystem::path& file) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(read_file(file));
  for (std::string line; std::getline(in, line);) {
    rows.emplace_back();
    std::istringstream cells(line);
    for (std::string cell; std::getline(cells, cell, ',');) rows.back().push_back(cell);
    if (!line.empty() && line.back() == ',') rows.back().push_back("");
  }
  return rows;
}

// A shell command's exit status (-1 if it did not exit) and what it printed
// on standard output (add 2>&1 to the command for its errors too).
struct CommandOutput {
  int status;
  std::string output;
};
inline CommandOutput run_command(const std::string& command) {
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return {-1, ""};
  std::string output;
  char buffer[512];
  while (fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

// The tissue a manifest's `tissue` object builds, for `seed`.
inline Tissue build_tissue(const json& spec, std::uint64_t seed = 1) {
  JsonReader reader(spec, "tissue");
  return make_tissue_builder(reader)->build(seed);
}

// A fresh, empty directory under the build tree's test scratch space.
inline std::filesystem::path scratch_dir(const std::string& name) {
  const auto dir = std::filesystem::path(FIBRODEM_BINARY_DIR) / "test_scratch" / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace fibrodem::testing
