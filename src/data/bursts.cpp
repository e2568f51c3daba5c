#include "sets/data/bursts.hpp"

#include <algorithm>
#include <cmath>

namespace sets {

double clipped_rms(const Eigen::Ref<const Eigen::VectorXd>& x) {
  double s = std::sqrt(x.squaredNorm() / static_cast<double>(std::max<Eigen::Index>(1, x.size())));
  for (int it = 0; it < 5; ++it) {
    double sum = 0;
    long kept = 0;
    for (Eigen::Index i = 0; i < x.size(); ++i)
      if (std::abs(x[i]) <= 3.5 * s) sum += x[i] * x[i], ++kept;
    if (kept < 10) break;
    const double next = std::sqrt(sum / static_cast<double>(kept)) / 0.9960;
    if (next == s) break;
    s = next;
  }
  return s;
}

double burst_ratio(const Eigen::Ref<const Eigen::VectorXd>& x, int max_order) {
  double worst = 1;
  Eigen::VectorXd d = x;
  for (int m = 1; m <= max_order && d.size() > 20; ++m) {
    d = (d.tail(d.size() - 1) - d.head(d.size() - 1)).eval();
    const double body = clipped_rms(d);
    if (!(body > 0)) continue;
    worst = std::max(worst, std::sqrt(d.squaredNorm() / static_cast<double>(d.size())) / body);
  }
  return worst;
}

}  // namespace sets
