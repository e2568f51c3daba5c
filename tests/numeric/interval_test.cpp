// Outward rounding of Interval, checked against exact rational arithmetic (CGAL::Gmpq) for
// + - * / and against 256-bit MPFR for sqrt, exp, sin and powers, in the optimised build.

#include <gtest/gtest.h>
#include <rapidcheck/gtest.h>

#include <CGAL/Gmpq.h>
#include <mpfr.h>

#include <cfenv>
#include <memory>
#include <variant>

#include "sets/numeric/interval.hpp"
#include "sets/numeric/interval_matrix.hpp"

namespace {

using sets::Interval;

// A reference value: exact rational while the tree is rational, MPFR once it is not.
struct Reference {
  bool exact = true;
  CGAL::Gmpq q;
  mpfr_t m;
  Reference() { mpfr_init2(m, 256); }
  ~Reference() { mpfr_clear(m); }
  Reference(const Reference&) = delete;
  void to_mpfr() {
    if (!exact) return;
    mpfr_set_q(m, q.mpq(), MPFR_RNDN);
    exact = false;
  }
};

// Is the reference inside [lo, hi]? Exact comparison for rationals; for MPFR the 256-bit
// value differs from the true one by far less than a double ulp, and an enclosure end that is
// exactly equal to a transcendental value cannot happen.
template <class I>
bool inside(const Reference& r, const I& x) {
  if (r.exact) return CGAL::Gmpq(x.lower()) <= r.q && r.q <= CGAL::Gmpq(x.upper());
  return mpfr_cmp_d(r.m, x.lower()) >= 0 && mpfr_cmp_d(r.m, x.upper()) <= 0;
}

enum class Op { leaf, add, sub, mul, div, sqrt, exp, sin, pow };

struct Node {
  Op op = Op::leaf;
  double value = 0;
  int power = 2;
  std::shared_ptr<Node> a, b;
};

rc::Gen<std::shared_ptr<Node>> gen_tree(int depth) {
  auto leaf = rc::gen::map(rc::gen::inRange(-2000000, 2000000), [](int v) {
    auto n = std::make_shared<Node>();
    n->value = v / 997.0;  // not a short binary fraction: products round
    return n;
  });
  if (depth == 0) return leaf;
  return rc::gen::oneOf(
      leaf,
      rc::gen::apply(
          [](int op, std::shared_ptr<Node> a, std::shared_ptr<Node> b, int power) {
            auto n = std::make_shared<Node>();
            n->op = static_cast<Op>(op);
            n->a = a;
            n->b = b;
            n->power = power;
            return n;
          },
          rc::gen::inRange(1, 9), gen_tree(depth - 1), gen_tree(depth - 1), rc::gen::inRange(0, 6)));
}

// Evaluates both ways; returns false if the expression is undefined (division by an interval
// containing 0, sqrt of a negative, overflow), in which case the sample is discarded. I is
// Interval, or UnprotectedInterval inside a RoundingScope.
template <class I>
bool evaluate(const Node& n, I& x, Reference& r) {
  if (n.op == Op::leaf) {
    x = I(n.value);
    r.q = CGAL::Gmpq(n.value);
    return true;
  }
  I xa, xb;
  Reference ra, rb;
  if (!evaluate(*n.a, xa, ra)) return false;
  const bool binary = n.op == Op::add || n.op == Op::sub || n.op == Op::mul || n.op == Op::div;
  if (binary && !evaluate(*n.b, xb, rb)) return false;
  const bool exact = ra.exact && (!binary || rb.exact);
  if (!exact || n.op == Op::sqrt || n.op == Op::exp || n.op == Op::sin) {
    ra.to_mpfr();
    if (binary) rb.to_mpfr();
  }
  r.exact = false;
  switch (n.op) {
    case Op::add:
      x = xa + xb;
      if (exact) { r.exact = true; r.q = ra.q + rb.q; } else mpfr_add(r.m, ra.m, rb.m, MPFR_RNDN);
      break;
    case Op::sub:
      x = xa - xb;
      if (exact) { r.exact = true; r.q = ra.q - rb.q; } else mpfr_sub(r.m, ra.m, rb.m, MPFR_RNDN);
      break;
    case Op::mul:
      x = xa * xb;
      if (exact) { r.exact = true; r.q = ra.q * rb.q; } else mpfr_mul(r.m, ra.m, rb.m, MPFR_RNDN);
      break;
    case Op::div:
      if (boost::numeric::zero_in(xb)) return false;
      x = xa / xb;
      if (exact) { r.exact = true; r.q = ra.q / rb.q; } else mpfr_div(r.m, ra.m, rb.m, MPFR_RNDN);
      break;
    case Op::sqrt:
      if (xa.lower() < 0) return false;
      x = boost::numeric::sqrt(xa);
      mpfr_sqrt(r.m, ra.m, MPFR_RNDN);
      break;
    case Op::exp:
      if (xa.upper() > 50) return false;
      x = boost::numeric::exp(xa);
      mpfr_exp(r.m, ra.m, MPFR_RNDN);
      break;
    case Op::sin:
      x = boost::numeric::sin(xa);
      mpfr_sin(r.m, ra.m, MPFR_RNDN);
      break;
    case Op::pow:
      x = boost::numeric::pow(xa, n.power);
      if (ra.exact) {
        r.exact = true;
        r.q = CGAL::Gmpq(1);
        for (int i = 0; i < n.power; ++i) r.q = r.q * ra.q;
      } else {
        mpfr_pow_ui(r.m, ra.m, static_cast<unsigned long>(n.power), MPFR_RNDN);
      }
      break;
    default: return false;
  }
  if (!std::isfinite(x.lower()) || !std::isfinite(x.upper())) return false;
  return true;
}

}  // namespace

RC_GTEST_PROP(Interval, RandomExpressionTreesEncloseTheExactValue, ()) {
  const auto tree = *gen_tree(4);
  Interval x;
  Reference r;
  RC_PRE(evaluate(*tree, x, r));
  RC_ASSERT(inside(r, x));
}

// The same trees in one RoundingScope with UnprotectedInterval (no mode switch per operation).
RC_GTEST_PROP(Interval, UnprotectedIntervalsInARoundingScopeEncloseTheExactValue, ()) {
  const auto tree = *gen_tree(4);
  sets::UnprotectedInterval x;
  Reference r;
  bool defined = false;
  {
    sets::RoundingScope upward;
    defined = evaluate(*tree, x, r);
  }
  RC_PRE(defined);
  RC_ASSERT(inside(r, x));
  RC_ASSERT(std::fegetround() == FE_TONEAREST);
}

TEST(Interval, OneThirdIsEnclosedInARoundingScope) {
  volatile double vone = 1.0, vthree = 3.0;
  const double one = vone, three = vthree;
  Interval x;
  {
    sets::RoundingScope upward;
    const sets::UnprotectedInterval q = sets::UnprotectedInterval(one) / sets::UnprotectedInterval(three);
    EXPECT_EQ(std::fegetround(), FE_UPWARD);
    x = q;  // to the protected type
    // A protected operation inside the scope restores the scope's mode, not round-to-nearest.
    x = x + Interval(one);
    EXPECT_EQ(std::fegetround(), FE_UPWARD);
    x = x - Interval(one);
  }
  EXPECT_EQ(std::fegetround(), FE_TONEAREST);
  const CGAL::Gmpq third(1, 3);
  EXPECT_LT(CGAL::Gmpq(x.lower()), third);
  EXPECT_GT(CGAL::Gmpq(x.upper()), third);
}

TEST(Interval, RoundingModeIsRestoredAfterUse) {
  const int before = std::fegetround();
  volatile double va = 1.0, vb = 3.0;
  const double a = va, b = vb;
  Interval x = Interval(a) / Interval(b);
  EXPECT_LT(x.lower(), x.upper()) << "1/3 is not a double: the enclosure must have width";
  EXPECT_EQ(std::fegetround(), before);
}

TEST(Interval, OneThirdIsEnclosedAtOptimisation) {
  // The classic failure of -O2 without -frounding-math: both ends folded to the same double.
  volatile double vone = 1.0, vthree = 3.0;
  const double one = vone, three = vthree;
  const Interval x = Interval(one) / Interval(three);
  const CGAL::Gmpq third(1, 3);
  EXPECT_LT(CGAL::Gmpq(x.lower()), third);
  EXPECT_GT(CGAL::Gmpq(x.upper()), third);
}

TEST(Interval, EvenPowerOfIntervalContainingZeroStartsAtZero) {
  const Interval x(-1.0, 2.0);
  const Interval sq = sets::pow(x, 2);
  EXPECT_EQ(sq.lower(), 0.0);
  EXPECT_GE(sq.upper(), 4.0);
  EXPECT_LE(sq.upper(), std::nextafter(4.0, 5.0));
  // Naive x*x gives [-2, 4]: that is the dependency problem the tight range avoids.
  EXPECT_LT((x * x).lower(), 0.0);
}

TEST(Interval, DecimalStringsAreEnclosed) {
  const Interval x = sets::interval_from_string("0.1");
  EXPECT_LT(CGAL::Gmpq(x.lower()), CGAL::Gmpq(1, 10));
  EXPECT_GT(CGAL::Gmpq(x.upper()), CGAL::Gmpq(1, 10));
  const Interval y = sets::interval_from_string("-2.5e-3");
  EXPECT_EQ(y.lower(), -2.5e-3);  // -0.0025 is not a double either, but must be within an ulp
  EXPECT_LE(y.upper() - y.lower(), 2 * std::numeric_limits<double>::epsilon() * 2.5e-3);
  EXPECT_THROW(sets::interval_from_string("1.2.3"), std::invalid_argument);
}

TEST(Interval, TranscendentalsStepOutward) {
  const Interval e = boost::numeric::exp(Interval(1.0));
  mpfr_t m;
  mpfr_init2(m, 256);
  mpfr_set_d(m, 1.0, MPFR_RNDN);
  mpfr_exp(m, m, MPFR_RNDN);
  EXPECT_GT(mpfr_cmp_d(m, e.lower()), 0);
  EXPECT_LT(mpfr_cmp_d(m, e.upper()), 0);
  mpfr_clear(m);
  const Interval s = boost::numeric::sin(Interval(1.5707963267948966));
  EXPECT_LE(s.upper(), 1.0);
}

TEST(IntervalMatrix, ProductEnclosesPointProducts) {
  Eigen::MatrixXd A(2, 2);
  A << 0.1, 0.2, 0.3, 0.7;
  Eigen::VectorXd lo(2), hi(2);
  lo << -1, 0.5;
  hi << 1, 0.6;
  const sets::IntervalVector box = sets::make_box(lo, hi);
  const sets::IntervalVector y = sets::multiply(A, box);
  for (double a : {-1.0, 0.0, 1.0})
    for (double b : {0.5, 0.55, 0.6}) {
      Eigen::Vector2d x(a, b);
      EXPECT_TRUE(sets::contains(y, A * x));
    }
  EXPECT_THROW(sets::make_box(hi, lo), std::invalid_argument);
}

#if defined(__x86_64__)
#include <xmmintrin.h>

namespace {
// Rounding-control bits of the two floating-point units on x86-64: SSE (MXCSR bits 13-14, what
// double arithmetic uses) and x87 (control word bits 10-11, what long double uses).
unsigned sse_rounding() { return (_mm_getcsr() >> 13) & 3u; }
unsigned x87_rounding() {
  unsigned short cw = 0;
  __asm__ volatile("fnstcw %0" : "=m"(cw));
  return (cw >> 10) & 3u;
}
}  // namespace

TEST(Interval, RoundingControlSetsBothSseAndX87AndRestoresThem) {
  ASSERT_EQ(sse_rounding(), 0u) << "tests must start in round-to-nearest";
  ASSERT_EQ(x87_rounding(), 0u);
  {
    Interval::traits_type::rounding scope;  // what every interval operation creates
    scope.upward();
    EXPECT_EQ(sse_rounding(), 2u) << "SSE not switched to upward";
    EXPECT_EQ(x87_rounding(), 2u) << "x87 not switched to upward";
  }
  EXPECT_EQ(sse_rounding(), 0u) << "SSE rounding mode not restored";
  EXPECT_EQ(x87_rounding(), 0u) << "x87 rounding mode not restored";
  {
    sets::RoundingScope outer;
    EXPECT_EQ(sse_rounding(), 2u);
    EXPECT_EQ(x87_rounding(), 2u);
    { sets::RoundingScope inner; }  // nested: restores the outer scope's mode
    EXPECT_EQ(sse_rounding(), 2u);
  }
  EXPECT_EQ(sse_rounding(), 0u) << "RoundingScope did not restore SSE";
  EXPECT_EQ(x87_rounding(), 0u) << "RoundingScope did not restore x87";
}
#endif

TEST(IntervalMatrix, ToIntervalHoldsTheDoublesExactly) {
  const Eigen::Vector3d v(0.1, -2.5, 1e300);
  Eigen::MatrixXd A(2, 3);
  A << 1, 2, 3, 4, 5, 6.5;
  const sets::IntervalVector iv = sets::to_interval(Eigen::VectorXd(v));  // plain VectorXd: unambiguous
  const sets::IntervalMatrix iA = sets::to_interval(A);
  const sets::IntervalVector iAv = sets::to_interval(A * v);  // an expression
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(iv[i].lower() == v[i] && iv[i].upper() == v[i]);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_TRUE(iA(i, j).lower() == A(i, j) && iA(i, j).upper() == A(i, j));
  const Eigen::Vector2d Av = A * v;
  for (int i = 0; i < 2; ++i) EXPECT_EQ(iAv[i].lower(), Av[i]);
}
