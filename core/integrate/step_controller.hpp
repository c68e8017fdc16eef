// Step-size control for an embedded pair whose error estimate is of order
// p + 1 in the step (p = 1 for first- against second-order Rush-Larsen):
// the PI controller of Gustafsson (1991, ACM TOMS 17:533), in the form of
// Hairer & Wanner, Solving ODEs II, IV.2 (eq. 2.43c):
//   h_new = h * fac * err_n^(-beta1) * err_{n-1}^(beta2),
// beta1 = 0.7/(p+1), beta2 = 0.4/(p+1), the factor clamped to [0.2, 5] (and
// to <= 1 right after a rejection). err is the estimate of the local error in
// units of the tolerance: a step is accepted when err <= 1. On a smooth
// stretch the controller settles where fac err^-(beta1 - beta2) = 1, i.e.
// err = fac^(1 / (beta1 - beta2)): 0.50 of the tolerance at H&W's fac = 0.9
// (p = 1), 0.09 at fac = 0.7.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

namespace fibrodem {

class StepController {
 public:
  explicit StepController(int order_p = 1, double safety = 0.9)
      : exponent_(1.0 / (order_p + 1)), safety_(safety) {}

  // The step to try after one of size h with error err (accepted or not).
  double next_step(double h, double err, bool accepted) {
    const double e = std::max(err, 1e-10);
    double factor;
    if (!accepted) {
      factor = std::clamp(safety_ * std::pow(e, -exponent_), 0.2, 0.9);
      rejected_last_ = true;
    } else {
      factor = safety_ * std::pow(e, -0.7 * exponent_) * std::pow(previous_error_, 0.4 * exponent_);
      factor = std::clamp(factor, 0.2, rejected_last_ ? 1.0 : 5.0);
      previous_error_ = std::max(e, 1e-4);
      rejected_last_ = false;
    }
    return h * factor;
  }
  // Forget the error history (after a jump in the right-hand side: a pulse edge).
  void restart() {
    previous_error_ = 1.0;
    rejected_last_ = false;
  }

 private:
  double exponent_, safety_;
  double previous_error_ = 1.0;
  bool rejected_last_ = false;
};

// Counts of the steps taken, in decades of step size, for run.log.
class StepHistogram {
 public:
  void add(double h_ms, bool accepted) {
    if (!accepted) {
      ++rejected_;
      return;
    }
    ++accepted_;
    min_ = std::min(min_, h_ms);
    max_ = std::max(max_, h_ms);
    const int decade = static_cast<int>(std::floor(std::log10(h_ms)));  // 1e-3 ms -> -3
    ++counts_[static_cast<std::size_t>(std::clamp(decade + kDecades - 1, 0, kDecades - 1))];
  }
  long long accepted() const { return accepted_; }
  long long rejected() const { return rejected_; }
  // "accepted 1234, rejected 12; dt [ms]: <1e-3: 0, [1e-3,1e-2): 40, ..."
  std::string describe() const;

 private:
  static constexpr int kDecades = 6;  // < 1e-4, [1e-4, 1e-3), ... , >= 1 ms
  std::array<long long, kDecades> counts_{};
  long long accepted_ = 0, rejected_ = 0;
  double min_ = INFINITY, max_ = 0;
};

}  // namespace fibrodem
