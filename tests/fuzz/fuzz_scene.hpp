// The small valid manifest the fuzz targets start from (a cell pair), for
// mutations to reach deep into the readers at once.
#pragma once

namespace fibrodem::fuzz {

inline const char* kCellPairManifest = R"({
  "fibrodem": 1, "name": "fuzz", "duration_ms": 100,
  "tissue": {"builder": "cell_pair", "fibroblasts": 2},
  "cells": {"myocyte": {"model": "colman"}, "fibroblast": {"model": "maleckar_active2"}},
  "coupling": {"D_f_nS": 2},
  "stimulus": [{"target": "myocyte", "start_ms": 10, "duration_ms": 2, "amplitude_pA": 2000}],
  "solver": {"method": "adaptive"},
  "output": {"traces": {"cells": [0], "variables": ["V"], "every_ms": 1}}
})";

}  // namespace fibrodem::fuzz
