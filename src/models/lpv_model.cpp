#include "sets/models/lpv_model.hpp"

#include <boost/algorithm/string/classification.hpp>
#include <boost/algorithm/string/trim.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/json_text.hpp"
#include "sets/core/error.hpp"

namespace sets {

// ---------------------------------------------------------------- basis functions

BasisFunction BasisFunction::of(int component, UnivariateFunction f) {
  if (component < 0) throw InputError("basis function: scheduling component must be >= 0");
  BasisFunction b;
  b.factors_.push_back({component, std::move(f)});
  return b;
}

BasisFunction BasisFunction::power(int component, int n) {
  if (n == 0) return BasisFunction();
  return of(component, UnivariateFunction::monomial(n));
}

BasisFunction BasisFunction::custom(std::string name, std::function<double(const Eigen::VectorXd&)> value,
                                    std::function<Interval(const IntervalVector&)> extension) {
  if (!value || !extension) throw InputError("custom basis function '" + name + "': value and extension are required");
  BasisFunction b;
  b.custom_name_ = std::move(name);
  b.custom_value_ = std::move(value);
  b.custom_extension_ = std::move(extension);
  return b;
}

BasisFunction operator*(const BasisFunction& a, const BasisFunction& b) {
  if (a.custom_value_ || b.custom_value_)
    throw UnsupportedError("basis functions: a custom basis function cannot be multiplied; write the product into it");
  BasisFunction r = a;
  r.scale_ = a.scale_ * b.scale_;
  for (const auto& fb : b.factors_) {
    auto it = std::find_if(r.factors_.begin(), r.factors_.end(),
                           [&](const BasisFunction::Factor& fa) { return fa.component == fb.component; });
    if (it == r.factors_.end())
      r.factors_.push_back(fb);
    else
      it->f = UnivariateFunction::product(it->f, fb.f);  // same variable: keep the range tight
  }
  std::sort(r.factors_.begin(), r.factors_.end(),
            [](const BasisFunction::Factor& x, const BasisFunction::Factor& y) { return x.component < y.component; });
  return r;
}

BasisFunction BasisFunction::scaled(double c) const {
  if (!std::isfinite(c)) throw InputError("basis function: scale must be finite");
  if (custom_value_) throw UnsupportedError("basis functions: a custom basis function cannot be scaled");
  BasisFunction r = *this;
  r.scale_ *= c;
  return r;
}

double BasisFunction::operator()(const Eigen::Ref<const Eigen::VectorXd>& lambda) const {
  if (custom_value_) return custom_value_(lambda);
  double v = scale_;
  for (const auto& f : factors_) v *= f.f(lambda[f.component]);
  return v;
}

namespace {

// Bisection range of a multivariate function from its box extension (custom basis functions).
Interval box_range(const std::function<Interval(const IntervalVector&)>& ext, const IntervalVector& box,
                   const RangeOptions& options) {
  const double kInf = std::numeric_limits<double>::infinity();
  double min_up = kInf, max_lo = -kInf;
  auto probe = [&](const IntervalVector& b) {
    IntervalVector c(b.size());
    for (Eigen::Index s = 0; s < b.size(); ++s) c[s] = Interval(midpoint(b[s]));
    const Interval v = ext(c);
    min_up = std::min(min_up, v.upper());
    max_lo = std::max(max_lo, v.lower());
  };
  std::vector<std::pair<IntervalVector, Interval>> pieces{{box, ext(box)}};
  probe(box);
  int examined = 1;
  for (;;) {
    double L = kInf, U = -kInf;
    for (const auto& pc : pieces) {
      L = std::min(L, pc.second.lower());
      U = std::max(U, pc.second.upper());
    }
    const double tl = options.tolerance * std::max(1.0, std::abs(L)), tu = options.tolerance * std::max(1.0, std::abs(U));
    if ((L >= min_up - tl && U <= max_lo + tu) || examined >= options.max_pieces) return Interval(L, U);
    std::vector<std::pair<IntervalVector, Interval>> next;
    bool split = false;
    for (const auto& pc : pieces) {
      Eigen::Index widest = 0;
      for (Eigen::Index s = 1; s < pc.first.size(); ++s)
        if (boost::numeric::width(pc.first[s]) > boost::numeric::width(pc.first[widest])) widest = s;
      const double a = pc.first[widest].lower(), b = pc.first[widest].upper(), m = midpoint(pc.first[widest]);
      const bool relevant = pc.second.lower() < min_up - tl || pc.second.upper() > max_lo + tu;
      if (!relevant || !(a < m && m < b) || examined >= options.max_pieces) {
        next.push_back(pc);
        continue;
      }
      IntervalVector left = pc.first, right = pc.first;
      left[widest] = Interval(a, m);
      right[widest] = Interval(m, b);
      probe(left);
      probe(right);
      next.emplace_back(left, ext(left));
      next.emplace_back(right, ext(right));
      ++examined;
      split = true;
    }
    pieces.swap(next);
    if (!split) {
      double L2 = kInf, U2 = -kInf;
      for (const auto& pc : pieces) {
        L2 = std::min(L2, pc.second.lower());
        U2 = std::max(U2, pc.second.upper());
      }
      return Interval(L2, U2);
    }
  }
}

}  // namespace

Interval BasisFunction::range(const IntervalVector& box, const RangeOptions& options) const {
  if (custom_value_) return box_range(custom_extension_, box, options);
  // The factors depend on different components, which vary independently over the box, so the
  // range of the product is the interval product of the factor ranges.
  Interval r(scale_);
  for (const auto& f : factors_) r = r * f.f.range(box[f.component], options).range;
  return r;
}

int BasisFunction::max_component() const {
  if (custom_value_) return -1;
  int m = -1;
  for (const auto& f : factors_) m = std::max(m, f.component);
  return m;
}

std::string BasisFunction::name(int alpha) const {
  if (custom_value_) return custom_name_;
  std::string s;
  if (scale_ != 1 || factors_.empty()) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", scale_);
    s = buf;
  }
  for (const auto& f : factors_) {
    const std::string var = alpha == 1 ? "lambda" : "l" + std::to_string(f.component + 1);
    std::string term = f.f.name();
    if (f.f.shape() == UnivariateFunction::Shape::polynomial) {
      std::string out;
      for (char c : term) out += c == 'x' ? var : std::string(1, c);
      term = out;
      if (term.find(' ') != std::string::npos) term = "(" + term + ")";
    } else {
      term += "(" + var + ")";
    }
    if (!s.empty()) s += "*";
    s += term;
  }
  return s;
}

namespace {

std::string trim(const std::string& s) { return boost::algorithm::trim_copy_if(s, boost::is_any_of(" \t")); }

int parse_variable(const std::string& v, int alpha, const std::string& text) {
  std::string digits;
  if (v == "lambda" || v == "l") {
    if (alpha != 1)
      throw InputError("basis function '" + text + "': with " + std::to_string(alpha) +
                       " scheduling variables write l1 ... l" + std::to_string(alpha));
    return 0;
  }
  if (v.rfind("lambda", 0) == 0)
    digits = v.substr(6);
  else if (v.rfind("l", 0) == 0)
    digits = v.substr(1);
  else
    throw InputError("basis function '" + text + "': '" + v + "' is not a scheduling variable (lambda, l1, l2, ...)");
  if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos)
    throw InputError("basis function '" + text + "': '" + v + "' is not a scheduling variable (lambda, l1, l2, ...)");
  const int k = std::stoi(digits);
  if (k < 1 || k > alpha)
    throw InputError("basis function '" + text + "': variable '" + v + "' is outside 1.." + std::to_string(alpha));
  return k - 1;
}

}  // namespace

BasisFunction parse_basis_function(const std::string& text, int alpha) {
  if (alpha < 1) throw InputError("basis function: alpha must be >= 1");
  BasisFunction result;
  std::string rest = text;
  if (trim(rest).empty()) throw InputError("basis function: empty text");
  std::size_t start = 0;
  while (start <= rest.size()) {
    const std::size_t star = rest.find('*', start);
    std::string factor = trim(rest.substr(start, star == std::string::npos ? std::string::npos : star - start));
    start = star == std::string::npos ? rest.size() + 1 : star + 1;
    if (factor.empty()) throw InputError("basis function '" + text + "': empty factor");
    // A number?
    char* end = nullptr;
    const double number = std::strtod(factor.c_str(), &end);
    if (end && *end == '\0' && end != factor.c_str()) {
      if (!std::isfinite(number)) throw InputError("basis function '" + text + "': number must be finite");
      result = result.scaled(number);
      continue;
    }
    // Optional integer power at the end: "...^n".
    int n = 1;
    const std::size_t caret = factor.rfind('^');
    if (caret != std::string::npos) {
      const std::string e = trim(factor.substr(caret + 1));
      if (e.empty() || e.find_first_not_of("0123456789") != std::string::npos || e.size() > 3)
        throw InputError("basis function '" + text + "': power '" + e + "' must be a small non-negative integer");
      n = std::stoi(e);
      factor = trim(factor.substr(0, caret));
    }
    const std::size_t paren = factor.find('(');
    if (paren == std::string::npos) {
      result = result * BasisFunction::power(parse_variable(factor, alpha, text), n);
      continue;
    }
    if (factor.back() != ')') throw InputError("basis function '" + text + "': missing ')' in '" + factor + "'");
    const std::string fname = trim(factor.substr(0, paren));
    const int component = parse_variable(trim(factor.substr(paren + 1, factor.size() - paren - 2)), alpha, text);
    const UnivariateFunction f = UnivariateFunction::builtin(fname);
    for (int k = 0; k < n; ++k) result = result * BasisFunction::of(component, f);
  }
  return result;
}

// ---------------------------------------------------------------- model structure

int LpvModelStructure::num_parameters() const {
  int p = 0;
  for (const auto& v : a) p += static_cast<int>(v.size());
  for (const auto& v : b) p += static_cast<int>(v.size());
  return p;
}

int LpvModelStructure::first_regression() const { return std::max(na(), std::max(nb(), 0)); }

std::vector<std::string> LpvModelStructure::parameter_names() const {
  // (ostringstream rather than "a" + std::to_string(..): GCC 12 warns falsely on the latter.)
  std::vector<std::string> names;
  auto add = [&](char c, std::size_t i, std::size_t k, const BasisFunction& f) {
    std::ostringstream os;
    os << c << i << ',' << k << '[' << f.name(alpha) << ']';
    names.push_back(os.str());
  };
  for (std::size_t i = 0; i < a.size(); ++i)
    for (std::size_t k = 0; k < a[i].size(); ++k) add('a', i + 1, k + 1, a[i][k]);
  for (std::size_t j = 0; j < b.size(); ++j)
    for (std::size_t h = 0; h < b[j].size(); ++h) add('b', j, h + 1, b[j][h]);
  return names;
}

void LpvModelStructure::validate() const {
  if (alpha < 1) throw InputError("LPV model: alpha (scheduling dimension) must be >= 1, got " + std::to_string(alpha));
  if (b.empty()) throw InputError("LPV model: b must list the bases of b_0 ... b_nb (use [] for an absent b_j)");
  if (num_parameters() == 0) throw InputError("LPV model: no parameter (every basis list is empty)");
  auto check = [&](const std::vector<std::vector<BasisFunction>>& v, const char* what, int offset) {
    for (std::size_t i = 0; i < v.size(); ++i)
      for (const auto& f : v[i])
        if (f.max_component() >= alpha)
          throw InputError(std::string("LPV model: basis '") + f.name(alpha) + "' of " + what +
                           std::to_string(static_cast<int>(i) + offset) + " uses scheduling component " +
                           std::to_string(f.max_component() + 1) + " > alpha = " + std::to_string(alpha));
  };
  check(a, "a", 1);
  check(b, "b", 0);
}

LpvModelStructure parse_lpv_structure_json(const std::string& text, const std::string& source) {
  // Malformed JSON and numbers beyond double (1e400) are InputErrors with line and column.
  nlohmann::json j = parse_json_text(text, source);
  if (!j.is_object()) throw InputError(source + ": expected a JSON object with fields alpha, a, b");
  LpvModelStructure m;
  if (j.contains("alpha")) {
    if (!j["alpha"].is_number_integer()) throw InputError(source + ": field 'alpha' must be an integer");
    m.alpha = j["alpha"].get<int>();
  }
  if (m.alpha < 1) throw InputError(source + ": field 'alpha' must be >= 1");
  auto lists = [&](const char* key, std::vector<std::vector<BasisFunction>>& out) {
    if (!j.contains(key)) throw InputError(source + ": missing field '" + key + "'");
    const auto& arr = j[key];
    if (!arr.is_array()) throw InputError(source + ": field '" + key + "' must be an array of arrays of strings");
    for (std::size_t i = 0; i < arr.size(); ++i) {
      if (!arr[i].is_array())
        throw InputError(source + ": field '" + key + "[" + std::to_string(i) + "]' must be an array of strings");
      std::vector<BasisFunction> basis;
      for (std::size_t k = 0; k < arr[i].size(); ++k) {
        const std::string where = source + ": field '" + key + "[" + std::to_string(i) + "][" + std::to_string(k) + "]'";
        if (!arr[i][k].is_string()) throw InputError(where + " must be a string such as \"lambda^2\"");
        try {
          basis.push_back(parse_basis_function(arr[i][k].get<std::string>(), m.alpha));
        } catch (const InputError& e) {
          throw InputError(where + ": " + e.what());
        }
      }
      out.push_back(std::move(basis));
    }
  };
  lists("a", m.a);
  lists("b", m.b);
  for (const auto& [key, value] : j.items())
    if (key != "alpha" && key != "a" && key != "b" && key != "na" && key != "nb")
      throw InputError(source + ": unknown field '" + key + "' (expected alpha, a, b)");
  if (j.contains("na") && j["na"] != m.na())
    throw InputError(source + ": field 'na' disagrees with the length of 'a'");
  if (j.contains("nb") && j["nb"] != m.nb())
    throw InputError(source + ": field 'nb' disagrees with the length of 'b' minus 1");
  m.validate();
  return m;
}

// ---------------------------------------------------------------- regression and PUIs

LpvRegression lpv_regression(const LpvModelStructure& model, const LpvMeasurements& data, const RangeOptions& range) {
  model.validate();
  const Eigen::Index T = data.u.size();
  const int alpha = model.alpha;
  const int p = model.num_parameters();
  if (data.y.size() != T || data.r.rows() != T)
    throw InputError("LPV data: u has " + std::to_string(T) + " samples, y " + std::to_string(data.y.size()) +
                     ", r " + std::to_string(data.r.rows()) + ": the lengths must match");
  if (data.r.cols() != alpha)
    throw InputError("LPV data: r has " + std::to_string(data.r.cols()) + " columns but the model has alpha = " +
                     std::to_string(alpha) + " scheduling variables");
  if (data.delta_eta.size() != T && data.delta_eta.size() != 1)
    throw InputError("LPV data: delta_eta must have 1 or " + std::to_string(T) + " entries");
  if ((data.delta_eps.rows() != T && data.delta_eps.rows() != 1) || data.delta_eps.cols() != alpha)
    throw InputError("LPV data: delta_eps must be 1 x alpha or T x alpha");
  auto deta = [&](Eigen::Index t) { return data.delta_eta[data.delta_eta.size() == 1 ? 0 : t]; };
  auto deps = [&](Eigen::Index t, int s) { return data.delta_eps(data.delta_eps.rows() == 1 ? 0 : t, s); };
  for (Eigen::Index t = 0; t < T; ++t) {
    const std::string where = "LPV data: sample " + std::to_string(t);
    if (!std::isfinite(data.u[t])) throw InputError(where + ", input u is not a finite number");
    if (!std::isfinite(data.y[t])) throw InputError(where + ", output y is not a finite number");
    for (int s = 0; s < alpha; ++s) {
      if (!std::isfinite(data.r(t, s)))
        throw InputError(where + ", scheduling measurement r" + std::to_string(s + 1) + " is not a finite number");
      if (!(deps(t, s) >= 0) || !std::isfinite(deps(t, s)))
        throw InputError(where + ", bound delta_eps" + std::to_string(s + 1) + " must be finite and >= 0 (got " +
                         std::to_string(deps(t, s)) + ")");
    }
    if (!(deta(t) >= 0) || !std::isfinite(deta(t)))
      throw InputError(where + ", bound delta_eta must be finite and >= 0 (got " + std::to_string(deta(t)) + ")");
  }
  const int n0 = model.first_regression();
  const Eigen::Index N = T - n0;
  if (N < p)
    throw InputError("LPV data: " + std::to_string(std::max<Eigen::Index>(N, 0)) + " regressions (" +
                     std::to_string(T) + " samples minus " + std::to_string(n0) + " initial ones) for " +
                     std::to_string(p) + " parameters: need at least as many regressions as parameters");

  LpvRegression reg;
  reg.Phi.resize(N, p);
  reg.Y.resize(N);
  reg.central.resize(N, p);
  reg.radius.resize(N, p);
  reg.time.resize(static_cast<std::size_t>(N));
  IntervalVector W(T);
  for (Eigen::Index t = 0; t < T; ++t) W[t] = interval_around(data.y[t], deta(t));  // eq. 20
  IntervalVector Lambda(alpha);
  for (Eigen::Index row = 0; row < N; ++row) {
    const Eigen::Index t = row + n0;
    reg.time[static_cast<std::size_t>(row)] = static_cast<int>(t);
    for (int s = 0; s < alpha; ++s) Lambda[s] = interval_around(data.r(t, s), deps(t, s));  // eq. 20
    int col = 0;
    auto basis_range = [&](const BasisFunction& f) { return f.range(Lambda, range); };  // eqs. 21–24
    for (int i = 1; i <= model.na(); ++i)
      for (const auto& f : model.a[static_cast<std::size_t>(i - 1)])
        reg.Phi(row, col++) = -(W[t - i] * basis_range(f));  // eqs. 16, 25
    for (int j = 0; j <= model.nb(); ++j)
      for (const auto& g : model.b[static_cast<std::size_t>(j)])
        reg.Phi(row, col++) = Interval(data.u[t - j]) * basis_range(g);  // eqs. 17, 26
    reg.Y[row] = W[t];
    for (int l = 0; l < p; ++l) {  // eqs. 27–34
      reg.central(row, l) = midpoint(reg.Phi(row, l));
      reg.radius(row, l) = radius(reg.Phi(row, l));
    }
  }
  return reg;
}

Eigen::VectorXd simulate_lpv(const LpvModelStructure& model, const Eigen::Ref<const Eigen::VectorXd>& theta,
                             const Eigen::Ref<const Eigen::VectorXd>& u, const Eigen::Ref<const Eigen::MatrixXd>& lambda) {
  model.validate();
  if (theta.size() != model.num_parameters())
    throw InputError("simulate_lpv: theta has " + std::to_string(theta.size()) + " entries, the model " +
                     std::to_string(model.num_parameters()) + " parameters");
  const Eigen::Index T = u.size();
  if (lambda.rows() != T || lambda.cols() != model.alpha)
    throw InputError("simulate_lpv: lambda must be T x alpha");
  Eigen::VectorXd w = Eigen::VectorXd::Zero(T);
  for (Eigen::Index t = 0; t < T; ++t) {
    const Eigen::VectorXd lam = lambda.row(t).transpose();
    double v = 0;
    int l = 0;
    for (int i = 1; i <= model.na(); ++i)
      for (const auto& f : model.a[static_cast<std::size_t>(i - 1)]) {
        if (t - i >= 0) v -= theta[l] * f(lam) * w[t - i];
        ++l;
      }
    for (int j = 0; j <= model.nb(); ++j)
      for (const auto& g : model.b[static_cast<std::size_t>(j)]) {
        if (t - j >= 0) v += theta[l] * g(lam) * u[t - j];
        ++l;
      }
    w[t] = v;
  }
  return w;
}

}  // namespace sets
