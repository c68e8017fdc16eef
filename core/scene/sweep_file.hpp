// A sweep file (docs/reference/sweep_file.md): a manifest run over the Cartesian
// product of parameter values.
//   { "fibrodem_sweep": 1,
//     "manifest": "cell_pair_active.json",          (relative to the sweep file)
//     "set":  { "duration_ms": 5000 },              (optional, every run)
//     "grid": { "tissue.fibroblasts": [1, 2, 4],
//               "coupling.D_f_nS": [0.5, 1, 2, 4, 8] },
//     "seeds": 5 }                                  (optional: K tissue seeds, or a list)
// With seeds, every grid point runs once per seed (the manifest's `seed` set
// to each), and the table gains statistics over the seeds.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "util/json_reader.hpp"

namespace fibrodem {

// One grid point: each grid path with its value, in the grid's order.
using SweepValues = std::vector<std::pair<std::string, json>>;

struct SweepFile {
  json base;                        // the manifest, with `set` (and the command line's --set) applied
  // Every run: the grid's product, the last path varying fastest, then with
  // seeds each point once per seed (its last value: "seed").
  std::vector<SweepValues> points;
  std::vector<long long> seeds;     // empty: "seeds" not given
};

// Reads a sweep file's JSON; `read_manifest` reads the manifest it names
// (relative paths resolved by the caller). Throws ManifestError naming the
// JSON path of a bad value.
// `overrides` (PATH=VALUE, as --set) apply after the file's own `set`.
SweepFile read_sweep(const json& sweep, const std::function<json(const std::string&)>& read_manifest,
                     const std::vector<std::string>& overrides = {});

// A point's manifest: the base with the point's values set (ManifestError,
// naming the path, for a value the manifest cannot take).
json point_manifest(const SweepFile& sweep, const SweepValues& point);

// PATH=VALUE as `--set` takes it.
std::string override_assignment(const std::string& path, const json& value);

}  // namespace fibrodem
