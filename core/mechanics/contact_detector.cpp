#include "mechanics/contact_detector.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace fibrodem {

ContactDetector::ContactDetector(std::vector<int> body, const std::vector<std::pair<int, int>>& bonded,
                                 double skin_m)
    : body_(std::move(body)), skin_(skin_m) {
  if (!(skin_ > 0)) throw std::invalid_argument("contact detection: the skin must be > 0");
  const std::size_t n = body_.size();
  partner_begin_.assign(n + 1, 0);
  for (const auto& [p, q] : bonded) {
    ++partner_begin_[p + 1];
    ++partner_begin_[q + 1];
  }
  for (std::size_t i = 0; i < n; ++i) partner_begin_[i + 1] += partner_begin_[i];
  partner_.resize(partner_begin_[n]);
  std::vector<int> fill(partner_begin_.begin(), partner_begin_.end() - 1);
  for (const auto& [p, q] : bonded) {
    partner_[fill[p]++] = q;
    partner_[fill[q]++] = p;
  }
  for (std::size_t i = 0; i < n; ++i)
    std::sort(partner_.begin() + partner_begin_[i], partner_.begin() + partner_begin_[i + 1]);
}

bool ContactDetector::bonded(int p, int q) const {
  const auto first = partner_.begin() + partner_begin_[p], last = partner_.begin() + partner_begin_[p + 1];
  return std::binary_search(first, last, q);
}

bool ContactDetector::needs_rebuild(const double* x, const double* y, const double* r) const {
  if (builds_ == 0) return true;
  double worst = 0;
  for (std::size_t i = 0; i < body_.size(); ++i) {
    const double dx = x[i] - x0_[i], dy = y[i] - y0_[i];
    worst = std::max(worst, std::sqrt(dx * dx + dy * dy) + std::max(0.0, r[i] - r0_[i]));
  }
  return 2 * worst > skin_;
}

void ContactDetector::build(const double* x, const double* y, const double* r,
                            std::vector<std::pair<int, int>>& pairs) {
  const std::size_t n = body_.size();
  pairs.clear();
  x0_.assign(x, x + n);
  y0_.assign(y, y + n);
  r0_.assign(r, r + n);
  ++builds_;
  if (n < 2) return;
  double xmin = x[0], xmax = x[0], ymin = y[0], ymax = y[0], rmax = r[0];
  for (std::size_t i = 1; i < n; ++i) {
    xmin = std::min(xmin, x[i]);
    xmax = std::max(xmax, x[i]);
    ymin = std::min(ymin, y[i]);
    ymax = std::max(ymax, y[i]);
    rmax = std::max(rmax, r[i]);
  }
  // Cells no smaller than the largest cut-off, and not many more than particles.
  double h = 2 * rmax + skin_;
  const double area = (xmax - xmin + h) * (ymax - ymin + h);
  h = std::max(h, std::sqrt(area / (4.0 * static_cast<double>(n))));
  const long nx = static_cast<long>((xmax - xmin) / h) + 1, ny = static_cast<long>((ymax - ymin) / h) + 1;
  const std::size_t ncell = static_cast<std::size_t>(nx * ny);
  // Counting sort of the particles by cell (stable: ascending index within a cell).
  cell_of_.resize(n);
  cell_start_.assign(ncell + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const long cx = std::min(nx - 1, static_cast<long>((x[i] - xmin) / h));
    const long cy = std::min(ny - 1, static_cast<long>((y[i] - ymin) / h));
    cell_of_[i] = static_cast<int>(cy * nx + cx);
    ++cell_start_[cell_of_[i] + 1];
  }
  for (std::size_t c = 0; c < ncell; ++c) cell_start_[c + 1] += cell_start_[c];
  order_.resize(n);
  cell_fill_.assign(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) order_[cell_fill_[cell_of_[i]]++] = static_cast<int>(i);
  for (std::size_t i = 0; i < n; ++i) {
    const int p = static_cast<int>(i);
    const long cx = cell_of_[i] % nx, cy = cell_of_[i] / nx;
    const std::size_t first = pairs.size();
    for (long gy = std::max(0L, cy - 1); gy <= std::min(ny - 1, cy + 1); ++gy)
      for (long gx = std::max(0L, cx - 1); gx <= std::min(nx - 1, cx + 1); ++gx) {
        const long c = gy * nx + gx;
        for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
          const int q = order_[k];
          if (q <= p || body_[q] == body_[p]) continue;
          const double dx = x[q] - x[i], dy = y[q] - y[i], cut = r[i] + r[q] + skin_;
          if (dx * dx + dy * dy >= cut * cut || bonded(p, q)) continue;
          pairs.emplace_back(p, q);
        }
      }
    std::sort(pairs.begin() + static_cast<long>(first), pairs.end());
  }
}

}  // namespace fibrodem
