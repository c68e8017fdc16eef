#include "integrate/step_controller.hpp"

#include <fmt/format.h>

namespace fibrodem {

std::string StepHistogram::describe() const {
  static const char* kBins[kDecades] = {"< 1e-4", "1e-4..1e-3", "1e-3..0.01", "0.01..0.1", "0.1..1", ">= 1"};
  std::string s = fmt::format("{} steps accepted, {} rejected", accepted_, rejected_);
  if (accepted_ == 0) return s;
  s += fmt::format("; dt from {:.3g} to {:.3g} ms; steps per dt range [ms]:", min_, max_);
  for (int k = 0; k < kDecades; ++k)
    if (counts_[k] > 0) s += fmt::format(" {}: {}", kBins[k], counts_[k]);
  return s;
}

}  // namespace fibrodem
