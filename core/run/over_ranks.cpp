#include "run/over_ranks.hpp"

#include "integrate/method_choice.hpp"
#include "tissue/tissue_builder.hpp"

namespace fibrodem {

std::vector<std::string> unsupported_over_ranks(const Scene& scene, const std::string& method) {
  std::vector<std::string> unsupported;
  if (!SolverSpec::fixed_step(method) && method != "adaptive")
    unsupported.push_back(scene.solver.method == "auto"
                              ? "solver.method \"auto\", which chose \"" + method +
                                    "\" (name \"adaptive\" or a fixed-step method: euler, rush_larsen, rush_larsen2)"
                              : "solver.method \"" + method +
                                    "\" (only \"adaptive\" and the fixed-step methods run split)");
  return unsupported;
}

std::vector<std::string> unsupported_over_ranks(const Scene& scene) {
  if (scene.solver.method != "auto") return unsupported_over_ranks(scene, scene.solver.method);
  const std::size_t cells = scene.tissue->cell_count(scene.seed);  // (not the tissue: its count alone)
  return unsupported_over_ranks(scene, choose_method(scene.solver, cells).solver.method);
}

CellLayoutKept cell_layout_kept(int rank, int ranks, bool mechanics, bool reentry) {
  if (ranks <= 1 || mechanics) return {};
  return {rank == 0 && reentry, rank == 0};
}

std::string refusal_over_ranks(const std::string& command, int ranks, const std::vector<std::string>& unsupported) {
  std::string text = "`fibrodem " + command + "` under mpirun with " + std::to_string(ranks) +
                     " ranks: this scene cannot be split over ranks yet; unsupported: ";
  for (std::size_t k = 0; k < unsupported.size(); ++k) text += (k ? "; " : "") + unsupported[k];
  return text + ". Nothing was written. Run it on one rank (mpirun -n 1, or without mpirun), or spread whole "
                "runs over ranks with `mpirun -n " + std::to_string(ranks) + " fibrodem sweep` (docs/guide/parallel.md)";
}

}  // namespace fibrodem
