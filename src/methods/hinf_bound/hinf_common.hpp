#pragma once
// Helpers shared by the sources of the four steps of hinf_bound (not installed).

#include <Eigen/Core>

#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

namespace sets::hinf_detail {

inline constexpr double pi = std::numbers::pi;

inline std::string num(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

// sum_k k^2 |c_k| >= sup_w |d^2/dw^2 c(e^{iw})|.
inline double polynomial_second_derivative_bound(const Eigen::Ref<const Eigen::VectorXd>& c) {
  double s = 0;
  for (Eigen::Index k = 0; k < c.size(); ++k) s += double(k) * k * std::abs(c[k]);
  return s;
}

}  // namespace sets::hinf_detail
