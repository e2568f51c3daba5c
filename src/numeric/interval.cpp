#include "sets/numeric/interval.hpp"

#include <ostream>
#include <sstream>
#include <iomanip>

#include <CGAL/Gmpq.h>

#include "sets/core/bool_interval.hpp"
#include "sets/core/error.hpp"

namespace sets {

Interval interval_from_string(const std::string& text) {
  // Parse the decimal exactly as a rational, then round it down and up.
  std::string s = text;
  std::size_t e = s.find_first_of("eE");
  long exponent = 0;
  if (e != std::string::npos) {
    try {
      exponent = std::stol(s.substr(e + 1));
    } catch (const std::exception&) {
      throw InputError("not a number: '" + text + "'");
    }
    s = s.substr(0, e);
  }
  bool negative = false;
  if (!s.empty() && (s[0] == '-' || s[0] == '+')) {
    negative = s[0] == '-';
    s = s.substr(1);
  }
  std::size_t dot = s.find('.');
  std::string digits = s;
  if (dot != std::string::npos) {
    digits = s.substr(0, dot) + s.substr(dot + 1);
    exponent -= static_cast<long>(s.size() - dot - 1);
  }
  if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos)
    throw InputError("not a number: '" + text + "'");
  digits.erase(0, std::min(digits.find_first_not_of('0'), digits.size() - 1));
  std::string num = digits, den = "1";
  if (exponent >= 0)
    num += std::string(static_cast<std::size_t>(exponent), '0');
  else
    den += std::string(static_cast<std::size_t>(-exponent), '0');
  CGAL::Gmpq q((negative ? "-" : "") + num + "/" + den);
  // Gmpq -> double is round-to-nearest; step one ulp outward unless exact.
  double d = q.to_double();
  CGAL::Gmpq back(d);
  double lo = d, hi = d;
  if (back > q) lo = std::nextafter(d, -std::numeric_limits<double>::infinity());
  if (back < q) hi = std::nextafter(d, std::numeric_limits<double>::infinity());
  return Interval(lo, hi);
}

Interval interval_around(double x, double r) {
  return Interval(x) + Interval(-r, r);
}

Interval pow(const Interval& x, const Interval& p) {
  if (x.lower() < 0) throw InputError("pow(x, p) with real p needs x >= 0");
  if (x.upper() == 0) return Interval(0.0);
  if (x.lower() == 0) {
    // exp(p log x) with log(0) = -inf: handle the lower end separately.
    Interval pos = boost::numeric::exp(p * boost::numeric::log(Interval(
        std::nextafter(0.0, 1.0), x.upper())));
    return Interval(p.lower() > 0 ? 0.0 : pos.lower(),
                    p.lower() > 0 ? pos.upper() : std::numeric_limits<double>::infinity());
  }
  return boost::numeric::exp(p * boost::numeric::log(x));
}

double midpoint(const Interval& x) { return boost::numeric::median(x); }

double radius(const Interval& x) {
  double m = midpoint(x);
  Interval d = boost::numeric::hull(Interval(x.upper()) - Interval(m), Interval(m) - Interval(x.lower()));
  return d.upper();
}

std::string to_string(const Interval& x) {
  std::ostringstream s;
  s << std::setprecision(17) << '[' << x.lower() << ", " << x.upper() << ']';
  return s.str();
}

std::ostream& operator<<(std::ostream& os, const Interval& x) {
  std::ostringstream s;
  s << std::setprecision(os.precision()) << '[' << x.lower() << ", " << x.upper() << ']';
  return os << s.str();
}

const char* to_string(BoolInterval b) {
  switch (b) {
    case BoolInterval::yes: return "yes";
    case BoolInterval::no: return "no";
    default: return "unknown";
  }
}
std::ostream& operator<<(std::ostream& os, BoolInterval b) { return os << to_string(b); }

}  // namespace sets
