// Tightness of the LPV PUIs for p = 2: the exact outer-approximated feasible set D'_theta
// (static-EIV description, eqs. 36–39; a union of one convex polygon per quadrant) is computed
// in exact rational arithmetic (CGAL::Gmpq) by clipping, and compared with the PUI box:
//   - the box must contain the polygon (guarantee) and touch its bounding box (tightness);
//   - the printed area ratio polygon / box says how much of the box the set fills.
// The figures go to docs/reproduction/cerone.md.

#include <gtest/gtest.h>

#include <CGAL/Gmpq.h>

#include <iomanip>
#include <iostream>
#include <random>

#include "sets/methods/lpv_pui/lpv_pui.hpp"

namespace {

using Q = CGAL::Gmpq;
struct Pt {
  Q x, y;
};

// Sutherland–Hodgman: keep the part of the convex polygon where a0 x + a1 y <= b.
std::vector<Pt> clip(const std::vector<Pt>& poly, const Q& a0, const Q& a1, const Q& b) {
  std::vector<Pt> out;
  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Pt& P = poly[i];
    const Pt& R = poly[(i + 1) % n];
    const Q fp = a0 * P.x + a1 * P.y - b, fr = a0 * R.x + a1 * R.y - b;
    if (fp <= 0) out.push_back(P);
    if ((fp < 0 && fr > 0) || (fp > 0 && fr < 0)) {
      const Q t = fp / (fp - fr);
      out.push_back({P.x + t * (R.x - P.x), P.y + t * (R.y - P.y)});
    }
  }
  return out;
}

Q area(const std::vector<Pt>& poly) {
  Q s = 0;
  for (std::size_t i = 0; i < poly.size(); ++i) {
    const Pt& P = poly[i];
    const Pt& R = poly[(i + 1) % poly.size()];
    s += P.x * R.y - R.x * P.y;
  }
  return s < 0 ? -s / 2 : s / 2;
}

struct Case {
  int N;
  double delta;
};

}  // namespace

TEST(LpvTightness, ExactPolygonOfTheStaticEivSetAgainstThePuiBox) {
  // w_t = -a lambda_t w_{t-1} + b u_{t-1}: theta = [a, b] = [0.5, 1], p = 2.
  sets::LpvModelStructure m;
  m.a = {{sets::BasisFunction::power(0, 1)}};
  m.b = {{}, {sets::BasisFunction()}};
  const Eigen::Vector2d theta(0.5, 1.0);
  std::cout << "    N    Delta E   area(D'_theta)/area(PUI box)   quadrants with a piece\n";
  for (const Case c : {Case{100, 4.8e-3}, Case{100, 4.8e-2}, Case{1000, 4.8e-3}, Case{1000, 4.8e-2}}) {
    std::mt19937_64 rng(static_cast<std::uint64_t>(c.N) * 7 + static_cast<std::uint64_t>(c.delta * 1e4));
    std::uniform_real_distribution<double> U(-1, 1);
    const int T = c.N + 1;
    Eigen::VectorXd u(T);
    Eigen::MatrixXd lambda(T, 1);
    for (int t = 0; t < T; ++t) u[t] = U(rng);
    for (int t = 0; t < T; ++t) lambda(t, 0) = U(rng);
    sets::LpvMeasurements d;
    d.u = u;
    d.y = sets::simulate_lpv(m, theta, u, lambda) + c.delta * Eigen::VectorXd::NullaryExpr(T, [&] { return U(rng); });
    d.r = lambda + c.delta * Eigen::MatrixXd::NullaryExpr(T, 1, [&] { return U(rng); });
    d.delta_eta = Eigen::VectorXd::Constant(1, c.delta);
    d.delta_eps = Eigen::MatrixXd::Constant(1, 1, c.delta);
    const auto res = sets::lpv_pui(m, d, {.orthants = sets::OrthantSelection::all});
    ASSERT_EQ(res.pui.consistency.falsified, sets::Falsified::no);
    ASSERT_TRUE(sets::contains(res.pui.box, theta));
    const auto& Phi = res.regression.Phi;
    const auto& Y = res.regression.Y;

    // Exact polygon per quadrant (eqs. 37–39 with the exact interval ends), clipped from a big square.
    const Q B = 100;
    Q total = 0, xmin, xmax, ymin, ymax;
    bool any = false;
    int pieces = 0;
    for (int sx : {1, -1})
      for (int sy : {1, -1}) {
        std::vector<Pt> poly = {{-B, -B}, {B, -B}, {B, B}, {-B, B}};
        poly = clip(poly, Q(-sx), Q(0), Q(0));  // sx * theta_1 >= 0
        poly = clip(poly, Q(0), Q(-sy), Q(0));  // sy * theta_2 >= 0
        for (Eigen::Index t = 0; t < Phi.rows() && !poly.empty(); ++t) {
          const double lo0 = sx > 0 ? Phi(t, 0).lower() : Phi(t, 0).upper();
          const double hi0 = sx > 0 ? Phi(t, 0).upper() : Phi(t, 0).lower();
          const double lo1 = sy > 0 ? Phi(t, 1).lower() : Phi(t, 1).upper();
          const double hi1 = sy > 0 ? Phi(t, 1).upper() : Phi(t, 1).lower();
          poly = clip(poly, Q(lo0), Q(lo1), Q(Y[t].upper()));      // eq. 37
          if (!poly.empty()) poly = clip(poly, Q(-hi0), Q(-hi1), Q(-Y[t].lower()));  // eq. 38
        }
        if (poly.empty()) continue;
        ++pieces;
        total += area(poly);
        for (const Pt& v : poly) {
          ASSERT_TRUE(v.x < B && v.x > -B && v.y < B && v.y > -B) << "set reaches the clipping square";
          if (!any || v.x < xmin) xmin = v.x;
          if (!any || v.x > xmax) xmax = v.x;
          if (!any || v.y < ymin) ymin = v.y;
          if (!any || v.y > ymax) ymax = v.y;
          any = true;
        }
      }
    ASSERT_TRUE(any);
    // Guarantee: the PUI box contains the exact set; tightness: it is the set's bounding box.
    const auto& box = res.pui.box;
    EXPECT_LE(Q(box[0].lower()), xmin);
    EXPECT_GE(Q(box[0].upper()), xmax);
    EXPECT_LE(Q(box[1].lower()), ymin);
    EXPECT_GE(Q(box[1].upper()), ymax);
    const double wx = box[0].upper() - box[0].lower(), wy = box[1].upper() - box[1].lower();
    EXPECT_NEAR(box[0].lower(), xmin.to_double(), 1e-7 * wx);
    EXPECT_NEAR(box[0].upper(), xmax.to_double(), 1e-7 * wx);
    EXPECT_NEAR(box[1].lower(), ymin.to_double(), 1e-7 * wy);
    EXPECT_NEAR(box[1].upper(), ymax.to_double(), 1e-7 * wy);
    const double ratio = total.to_double() / (wx * wy);
    EXPECT_GT(ratio, 0.0);
    EXPECT_LE(ratio, 1.0 + 1e-9);
    std::cout << std::setw(6) << c.N << std::setw(11) << c.delta << std::setw(20) << std::setprecision(3) << ratio
              << std::setw(26) << pieces << "   (PUI half-widths " << std::setprecision(2) << wx / 2 << ", " << wy / 2
              << ")\n";
  }
}
