#include "sets/methods/ss_uncertainty/canonical_fps.hpp"

#include <numeric>
#include <string>

#include "sets/core/error.hpp"

namespace sets {
namespace {

bool is_zero(const Interval& x) { return x.lower() == 0 && x.upper() == 0; }
bool is_zero(double x) { return x == 0; }

int find_root(std::vector<int>& parent, int j) {
  while (parent[j] != j) j = parent[j] = parent[parent[j]];
  return j;
}

// The grouping of both constructors, for interval or exact regressors. Loops run down the
// columns (the matrices are column-major: a 5 000 x 12 regression read row by row misses the
// cache on every entry).
template <class Matrix>
void group_rows(const Matrix& Psi, const IntervalVector& Y, std::vector<CanonicalFps::Block>& blocks,
                std::vector<int>& falsified) {
  if (Psi.rows() != Y.size())
    throw InputError("CanonicalFps: " + std::to_string(Psi.rows()) + " regressor rows but " +
                     std::to_string(Y.size()) + " outputs");
  const int p = static_cast<int>(Psi.cols());
  // Union-find over the parameters: a row joins every parameter it involves.
  std::vector<int> parent(static_cast<std::size_t>(p));
  std::iota(parent.begin(), parent.end(), 0);
  std::vector<int> first_column(static_cast<std::size_t>(Psi.rows()), -1);
  for (int j = 0; j < p; ++j)
    for (Eigen::Index t = 0; t < Psi.rows(); ++t) {
      if (is_zero(Psi(t, j))) continue;
      int& f = first_column[static_cast<std::size_t>(t)];
      if (f < 0) f = j;
      else parent[static_cast<std::size_t>(find_root(parent, j))] = find_root(parent, f);
    }
  std::vector<int> block_of_root(static_cast<std::size_t>(p), -1);
  for (Eigen::Index t = 0; t < Psi.rows(); ++t) {
    const int f = first_column[static_cast<std::size_t>(t)];
    if (f < 0) {
      if (!(Y[t].lower() <= 0 && 0 <= Y[t].upper())) falsified.push_back(static_cast<int>(t));
      continue;
    }
    int& b = block_of_root[static_cast<std::size_t>(find_root(parent, f))];
    if (b < 0) {
      b = static_cast<int>(blocks.size());
      blocks.emplace_back();
    }
    blocks[static_cast<std::size_t>(b)].rows.push_back(static_cast<int>(t));
  }
  for (int j = 0; j < p; ++j) {
    const int b = block_of_root[static_cast<std::size_t>(find_root(parent, j))];
    if (b < 0)
      throw InputError("CanonicalFps: parameter " + std::to_string(j) + " appears in no row (it is not identifiable)");
    blocks[static_cast<std::size_t>(b)].parameters.push_back(j);
  }
  for (CanonicalFps::Block& block : blocks) {
    const auto n = static_cast<Eigen::Index>(block.rows.size());
    const auto m = static_cast<Eigen::Index>(block.parameters.size());
    IntervalMatrix phi(n, m);
    IntervalVector y(n);
    for (Eigen::Index q = 0; q < m; ++q)
      for (Eigen::Index k = 0; k < n; ++k) phi(k, q) = Interval(Psi(block.rows[k], block.parameters[q]));
    for (Eigen::Index k = 0; k < n; ++k) y[k] = Y[block.rows[k]];
    block.set = FeasibleParameterSet::from_interval_data(phi, y);
  }
}

}  // namespace

CanonicalFps::CanonicalFps(const IntervalMatrix& Psi, const IntervalVector& Y)
    : dimension_(static_cast<int>(Psi.cols())) {
  group_rows(Psi, Y, blocks_, falsified_);
}

CanonicalFps::CanonicalFps(const Eigen::MatrixXd& Psi, const IntervalVector& Y)
    : dimension_(static_cast<int>(Psi.cols())) {
  group_rows(Psi, Y, blocks_, falsified_);
}

int CanonicalFps::size() const {
  int n = 0;
  for (const Block& b : blocks_) n += b.set.size();
  return n;
}

bool CanonicalFps::has_interval_regressors() const {
  for (const Block& b : blocks_)
    if (b.set.has_interval_regressors()) return true;
  return false;
}

BoolInterval CanonicalFps::contains(const Eigen::Ref<const Eigen::VectorXd>& theta) const {
  if (theta.size() != dimension_) throw InputError("CanonicalFps::contains: wrong dimension");
  if (!falsified_.empty()) return BoolInterval::no;
  BoolInterval result = BoolInterval::yes;
  for (const Block& b : blocks_) {
    Eigen::VectorXd part(static_cast<Eigen::Index>(b.parameters.size()));
    for (std::size_t q = 0; q < b.parameters.size(); ++q) part[static_cast<Eigen::Index>(q)] = theta[b.parameters[q]];
    const BoolInterval v = b.set.contains(part);
    if (v == BoolInterval::no) return v;
    if (v == BoolInterval::unknown) result = v;
  }
  return result;
}

PuiResult pui(const CanonicalFps& fps, const PuiOptions& options) {
  PuiResult r;
  const int p = fps.dimension();
  if (!fps.falsified_rows().empty()) {
    r.consistency.falsified = Falsified::yes;  // 0 outside an output interval is decided exactly
    r.guaranteed = true;
    r.consistency.conflict.samples = fps.falsified_rows();
    r.consistency.conflict.violation.assign(r.consistency.conflict.samples.size(), 0.0);
    return r;
  }
  r.box.resize(p);
  r.lower_points.resize(p, p);
  r.upper_points.resize(p, p);
  r.guaranteed = true;
  r.consistency.falsified = Falsified::no;  // the set is the product of the blocks' sets
  std::vector<PuiResult> parts;
  for (const CanonicalFps::Block& b : fps.blocks()) {
    parts.push_back(pui(b.set, options));
    PuiResult& part = parts.back();
    r.lp_solves += part.lp_solves;
    r.guaranteed = r.guaranteed && part.guaranteed;
    if (part.empty()) {
      r.consistency = part.consistency;
      r.box = IntervalVector();
      for (int& s : r.consistency.conflict.samples) s = b.rows[static_cast<std::size_t>(s)];
      return r;
    }
    if (part.consistency.falsified == Falsified::unknown && r.consistency.falsified == Falsified::no)
      r.consistency = part.consistency;  // undecided block: the product is undecided unless another is empty
    for (std::size_t q = 0; q < b.parameters.size(); ++q) r.box[b.parameters[q]] = part.box[static_cast<Eigen::Index>(q)];
  }
  // Attaining points: a block's own point in its parameters, one feasible point of every other
  // block elsewhere (the set is their product, so the combination is feasible).
  const auto& blocks = fps.blocks();
  for (std::size_t a = 0; a < blocks.size(); ++a)
    for (std::size_t q = 0; q < blocks[a].parameters.size(); ++q) {
      const int l = blocks[a].parameters[q];
      for (std::size_t b = 0; b < blocks.size(); ++b) {
        const Eigen::Index col = b == a ? static_cast<Eigen::Index>(q) : 0;
        for (std::size_t s = 0; s < blocks[b].parameters.size(); ++s) {
          r.lower_points(blocks[b].parameters[s], l) = parts[b].lower_points(static_cast<Eigen::Index>(s), col);
          r.upper_points(blocks[b].parameters[s], l) = parts[b].upper_points(static_cast<Eigen::Index>(s), col);
        }
      }
    }
  r.central = midpoint(r.box);
  return r;
}

}  // namespace sets
