#include "sets/examples/diagnosis_suite.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include "sets/examples/random_plants.hpp"
#include "sets/numeric/worker_threads.hpp"

namespace sets {

bool SuitePlantResult::first_right() const {
  if (truth.empty()) return named.empty() && error.empty();
  return !named.empty() && named.front() == truth.front().name;
}

bool SuitePlantResult::all_named() const {
  for (const auto& t : truth)
    if (std::find(named.begin(), named.end(), t.name) == named.end()) return false;
  return error.empty();
}

namespace {

bool among(const std::vector<EquallyGood>& alike, const std::string& effect) {
  for (const auto& a : alike)
    if (std::find(a.effects.begin(), a.effects.end(), effect) != a.effects.end()) return true;
  return false;
}

}  // namespace

bool SuitePlantResult::first_right_or_equally_good() const {
  return first_right() || (!truth.empty() && !equally_good.empty() && among(equally_good.front(), truth.front().name));
}

bool SuitePlantResult::all_named_or_equally_good() const {
  for (const auto& t : truth) {
    bool found = std::find(named.begin(), named.end(), t.name) != named.end();
    for (const auto& alike : equally_good) found = found || among(alike, t.name);
    if (!found) return false;
  }
  return error.empty();
}

namespace {

bool holds(double lo, double hi, double x) { return lo <= x && x <= hi; }

SuiteCoverage coverage_of(const std::string& effect, const std::string& role, double truth, const EffectParameter& ep) {
  SuiteCoverage c;
  c.effect = effect;
  c.role = role;
  c.truth = truth;
  c.lo = ep.lo, c.hi = ep.hi, c.estimate = ep.estimate;
  c.estimate_oe_lo = ep.estimate_oe_lo, c.estimate_oe_hi = ep.estimate_oe_hi;
  c.has_ee = ep.has_ee, c.ee_certified = ep.ee_certified, c.ee_lo = ep.ee_lo, c.ee_hi = ep.ee_hi;
  c.estimate_stat_lo = ep.estimate_stat_lo, c.estimate_stat_hi = ep.estimate_stat_hi;
  c.bounded = ep.has_bounded_error_interval();
  c.inside = holds(ep.lo, ep.hi, truth);
  c.inside_estimate = holds(ep.estimate_oe_lo, ep.estimate_oe_hi, truth);
  // The rule before: the meet of both PUIs (their hull when disjoint).
  double lo = ep.estimate_oe_lo, hi = ep.estimate_oe_hi;
  if (ep.has_ee) {
    const bool meet = ep.ee_lo <= hi && lo <= ep.ee_hi;
    lo = meet ? std::max(lo, ep.ee_lo) : std::min(lo, ep.ee_lo);
    hi = meet ? std::min(hi, ep.ee_hi) : std::max(hi, ep.ee_hi);
  }
  c.inside_meet = holds(lo, hi, truth);
  return c;
}

}  // namespace

SuitePlantResult run_suite_plant(const SyntheticPlant& p, const DiagnosisOptions& options) {
  SuitePlantResult r;
  r.name = p.name;
  r.family = p.family;
  r.description = p.description;
  r.truth = p.effects;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    const Diagnosis d = diagnose(p.nominal, p.estimation, &p.validation, options);
    for (const auto& e : d.effects) r.named.push_back(e.name), r.places.push_back(e.equation), r.equally_good.push_back(e.equally_good);
    r.answer = d.nothing_missing ? "nothing_missing" : d.unexplained ? "unexplained" : "missing";
    r.fit_nominal = d.fit_nominal_validation.empty() ? 0 : d.fit_nominal_validation.front();
    r.fit_augmented = d.fit_augmented_validation.empty() ? 0 : d.fit_augmented_validation.front();
    // Against the truth of the record the estimate was read from (the generators scale the noise
    // to each record's own signal spread, so the two records' truths differ).
    auto ratio = [&](const OutputNoise& n, std::size_t j) {
      const bool val = n.record == "validation" && j < p.noise_sigma_validation.size();
      const double truth = val ? p.noise_sigma_validation[j] : p.noise_sigma[j];
      return truth > 0 ? n.estimate.sigma / truth : 0.0;
    };
    for (std::size_t j = 0; j < d.noise_final.size() && j < p.noise_sigma.size(); ++j) r.noise_ratio.push_back(ratio(d.noise_final[j], j));
    for (std::size_t j = 0; j < d.noise.size() && j < p.noise_sigma.size(); ++j) r.noise_ratio_nominal.push_back(ratio(d.noise[j], j));
    // Coverage: true values that map cleanly, for effects named at the place they are.
    for (const auto& t : p.effects)
      for (const auto& e : d.effects) {
        if (e.name != t.name || e.equation != t.where) continue;
        for (const auto& [role, value] : t.values)
          for (const auto& ep : e.parameters)
            if (ep.role == role)
              r.coverage.push_back(coverage_of(t.name, role, value, ep));
      }
  } catch (const std::exception& e) {
    r.error = e.what();
    r.answer = "error";
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

namespace {

std::vector<SuitePlantResult> run_all(int count, const std::function<SyntheticPlant(int)>& plant, const SuiteOptions& o) {
  std::vector<SuitePlantResult> out(static_cast<std::size_t>(count));
  std::atomic<int> next{0}, done{0};
  std::mutex mu;
  run_worker_threads(o.threads, [&] {
    for (int i; (i = next++) < count;) {
      DiagnosisOptions d = o.diagnosis;
      d.threads = 1;
      d.progress = nullptr;
      SuitePlantResult r;
      try {
        r = run_suite_plant(plant(i), d);
      } catch (const std::exception& e) {  // the plant itself could not be generated
        r.name = "plant " + std::to_string(i);
        r.error = e.what();
        r.answer = "error";
      }
      std::lock_guard<std::mutex> lock(mu);
      out[static_cast<std::size_t>(i)] = r;
      ++done;
      if (o.on_plant) o.on_plant(out[static_cast<std::size_t>(i)], done, count);
    }
  });
  return out;
}

std::string pct(int a, int b) {
  std::ostringstream o;
  o << a << " of " << b;
  if (b > 0) o << " (" << std::fixed << std::setprecision(1) << 100.0 * a / b << " %)";
  return o.str();
}

std::string interval(double lo, double hi) {
  std::ostringstream o;
  o << std::setprecision(4) << "[" << lo << ", " << hi << "]";
  return o.str();
}

// Every true value outside its bounded-error interval, its linearised estimate or their meet (the
// rule before), with the sets involved: says which set missed and whether that set is guaranteed.
std::string coverage_misses(const std::vector<SuitePlantResult>& results) {
  std::ostringstream o;
  int n = 0;
  for (const auto& r : results)
    for (const auto& c : r.coverage) {
      if (c.inside && c.inside_estimate && c.inside_meet) continue;
      if (n++ == 0)
        o << "\nTrue values outside an interval (bounded-error: the certified equation-error PUI met with the declared range; "
             "estimate: the output-error PUI linearised at the estimate; meet: the two met, the rule before):\n\n"
             "| plant | effect | role | true | bounded-error | estimate | estimate: output-error PUI | equation-error PUI | "
             "estimate: 95 % statistical | outside |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
      std::string outside;
      if (c.bounded && !c.inside) outside += "bounded-error";
      if (!c.inside_estimate) outside += std::string(outside.empty() ? "" : ", ") + "estimate";
      if (!c.inside_meet) outside += std::string(outside.empty() ? "" : ", ") + "meet";
      o << "| " << r.name << " | " << c.effect << " | " << c.role << " | " << std::setprecision(4) << c.truth << " | "
        << (c.bounded ? interval(c.lo, c.hi) : std::string("none")) << " | " << std::setprecision(4) << c.estimate << " | "
        << interval(c.estimate_oe_lo, c.estimate_oe_hi) << " | "
        << (c.has_ee ? interval(c.ee_lo, c.ee_hi) + (c.ee_certified ? "" : " (not certified)") : std::string("–")) << " | "
        << interval(c.estimate_stat_lo, c.estimate_stat_hi) << " | " << outside << " |\n";
    }
  return o.str();
}

// The headline figures of one plant family (one- and two-mass mechanics, motors, ...): where the
// rules are weak shows here, not in the suite's totals.
struct FamilyTally {
  int one = 0, one_right = 0, two = 0, two_both = 0, clean = 0, clean_invented = 0;
};

// The counts behind the suite's figures, in one pass over the plants.
struct SuiteTally {
  int one = 0, one_right = 0, two = 0, two_both = 0, two_one = 0, clean = 0, clean_invented = 0, clean_nothing = 0, errors = 0;
  int one_right_alike = 0, two_both_alike = 0, named = 0, alike = 0, plants_alike = 0;  // the lenient figures
  int cov = 0, cov_bounded = 0, cov_in = 0, cov_estimate = 0, cov_meet = 0, right_place = 0, named_true = 0;
  double seconds = 0;
  std::vector<double> ratios, ratios_nominal;
  std::map<std::string, std::map<std::string, int>> confusion;
  std::map<std::string, int> tp, fp, fn;
  std::set<std::string> labels{"none"};
  std::map<std::string, FamilyTally> families;
};

SuiteTally tally(const std::vector<SuitePlantResult>& results) {
  SuiteTally t;
  for (const auto& r : results) {
    t.seconds += r.seconds;
    if (!r.error.empty()) ++t.errors;
    for (double x : r.noise_ratio) t.ratios.push_back(x);
    for (double x : r.noise_ratio_nominal) t.ratios_nominal.push_back(x);
    std::vector<std::string> truth;
    for (const auto& e : r.truth) truth.push_back(e.name);
    FamilyTally none;  // the fixed suite's plants have no family
    FamilyTally& f = r.family.empty() ? none : t.families[r.family];
    if (truth.empty()) {
      ++t.clean;
      t.clean_invented += !r.named.empty();
      t.clean_nothing += r.answer == "nothing_missing";
      ++f.clean, f.clean_invented += !r.named.empty();
    } else if (truth.size() == 1) {
      ++t.one;
      t.one_right += r.first_right();
      t.one_right_alike += r.first_right_or_equally_good();
      ++f.one, f.one_right += r.first_right();
    } else {
      ++t.two;
      t.two_both += r.all_named();
      ++f.two, f.two_both += r.all_named();
      t.two_both_alike += r.all_named_or_equally_good();
      int n = 0;
      for (const auto& e : truth) n += std::find(r.named.begin(), r.named.end(), e) != r.named.end();
      t.two_one += n >= 1;
    }
    int listed = 0;
    for (const auto& a : r.equally_good) listed += static_cast<int>(a.size());
    t.named += static_cast<int>(r.named.size()), t.alike += listed, t.plants_alike += listed > 0;
    if (truth.size() <= 1) {
      const std::string row = truth.empty() ? "none" : truth.front(), col = r.named.empty() ? "none" : r.named.front();
      ++t.confusion[row][col];
      t.labels.insert(row);
      t.labels.insert(col);
    }
    for (const auto& e : truth) (std::find(r.named.begin(), r.named.end(), e) != r.named.end() ? t.tp : t.fn)[e]++;
    for (const auto& n : r.named)
      if (std::find(truth.begin(), truth.end(), n) == truth.end()) t.fp[n]++;
    for (std::size_t k = 0; k < r.named.size(); ++k)
      for (const auto& e : r.truth)
        if (e.name == r.named[k]) ++t.named_true, t.right_place += e.where == r.places[k];
    for (const auto& c : r.coverage)
      ++t.cov, t.cov_bounded += c.bounded, t.cov_in += c.bounded && c.inside, t.cov_estimate += c.inside_estimate, t.cov_meet += c.inside_meet;
  }
  return t;
}

// "coulomb_friction + constant_offset 1.37 sigma": truncated to two decimals, so that the printed
// value falls below the generator's threshold exactly when the measured one does.
std::string special_case_text(const TrueEffect& t) {
  std::ostringstream x;
  for (std::size_t k = 0; k < t.special_case.size(); ++k) x << (k ? " + " : "") << t.special_case[k];
  if (t.detectability_vs_special_case < 0) x << " unknown";
  else x << " " << std::fixed << std::setprecision(2) << std::floor(100 * t.detectability_vs_special_case) / 100 << " sigma";
  return x.str();
}

// One row per plant.
void write_plant_table(std::ostream& o, const std::vector<SuitePlantResult>& results) {
  o << "| plant | family | true effects (where, strength) | named (where) | answer | first right | all named | fit val: nominal -> augmented | "
       "noise est/true: final (nominal's if different) | true values inside: bounded-error; estimate | s |\n"
       "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n";
  for (const auto& r : results) {
    std::string truth, named;
    for (const auto& t : r.truth) {
      std::ostringstream x;
      x << t.name << " (" << t.where << ", " << std::round(100 * t.strength) << " %";
      if (t.detectability > 0) x << ", " << std::setprecision(2) << t.detectability << " sigma" << std::setprecision(1);
      if (!t.special_case.empty()) x << ", vs " << special_case_text(t);
      x << ")";
      truth += (truth.empty() ? "" : ", ") + x.str();
    }
    for (std::size_t k = 0; k < r.named.size(); ++k) named += (k ? ", " : "") + r.named[k] + " (" + r.places[k] + ")";
    o << "| " << r.name << " | " << r.family << " | " << (truth.empty() ? "none" : truth) << " | " << (named.empty() ? "none" : named)
      << " | " << (r.error.empty() ? r.answer : "error: " + r.error) << " | " << (r.first_right() ? "yes" : "**no**") << " | "
      << (r.all_named() ? "yes" : "**no**") << " | " << r.fit_nominal << " -> " << r.fit_augmented << " | ";
    for (std::size_t j = 0; j < r.noise_ratio.size(); ++j) {
      o << (j ? ", " : "") << std::setprecision(2) << r.noise_ratio[j];
      if (j < r.noise_ratio_nominal.size() && r.noise_ratio_nominal[j] != r.noise_ratio[j]) o << " (" << r.noise_ratio_nominal[j] << ")";
    }
    int bounded = 0, inside = 0, inside_estimate = 0;
    for (const auto& c : r.coverage) bounded += c.bounded, inside += c.bounded && c.inside, inside_estimate += c.inside_estimate;
    o << std::setprecision(1) << " | " << inside << " of " << bounded << "; " << inside_estimate << " of " << r.coverage.size()
      << " | " << r.seconds << " |\n";
  }
  o << "\n";
}

// The plants whose named effects list equally good alternatives (a table of its own: the plant
// table's columns stay as they were, for the scripts that read it).
void write_equally_good(std::ostream& o, const std::vector<SuitePlantResult>& results) {
  bool any = false;
  for (const auto& r : results)
    for (std::size_t k = 0; k < r.equally_good.size(); ++k) {
      if (r.equally_good[k].empty()) continue;
      if (!any) o << "Equally good on these data (alternatives the data cannot tell from a named effect):\n\n"
                     "| plant | true effects | named (rank. effect (where)) | equally good (misfit: share of the model's before it) | "
                     "true effects among them |\n| --- | --- | --- | --- | --- |\n";
      any = true;
      std::string truth, alike, hit;
      for (const auto& t : r.truth) {
        truth += (truth.empty() ? "" : ", ") + t.name + " (" + t.where + ")";
        if (among(r.equally_good[k], t.name)) hit += (hit.empty() ? "" : ", ") + t.name;
      }
      for (const auto& a : r.equally_good[k]) {
        std::ostringstream x;
        for (std::size_t q = 0; q < a.effects.size(); ++q) x << (q ? " + " : "") << a.effects[q] << " (" << a.equations[q] << ")";
        x << std::fixed << std::setprecision(1) << " misfit " << 100 * a.misfit << " %";
        alike += (alike.empty() ? "" : "; ") + x.str();
      }
      o << "| " << r.name << " | " << (truth.empty() ? "none" : truth) << " | " << k + 1 << ". " << r.named[k] << " (" << r.places[k]
        << ") | " << alike << " | " << (hit.empty() ? "none" : hit) << " |\n";
    }
  if (any) o << "\n";
}

void write_summary(std::ostream& o, const SuiteTally& t, std::size_t plants) {
  o << "Plants: " << plants << " (" << t.one << " with one effect, " << t.two << " with two, " << t.clean << " clean; " << t.errors
    << " failed); " << t.seconds << " s of diagnosis in all (" << (plants == 0 ? 0.0 : t.seconds / static_cast<double>(plants))
    << " s per plant).\n\n";
  o << "- one-effect plants, first named right: " << pct(t.one_right, t.one) << "\n";
  o << "- two-effect plants, both named: " << pct(t.two_both, t.two) << " (at least one: " << pct(t.two_one, t.two) << ")\n";
  o << "- declared second figures, lenient: right or the truth among the named effects' equally good alternatives "
       "(one-effect: the first named effect's): one-effect " << pct(t.one_right_alike, t.one) << ", two-effect both "
    << pct(t.two_both_alike, t.two) << "; alternatives listed: " << t.alike << " for " << t.named << " named effects ("
    << std::setprecision(2) << (t.named ? static_cast<double>(t.alike) / t.named : 0.0) << std::setprecision(1)
    << " per named effect), on " << t.plants_alike << " plants\n";
  o << "- clean plants with an invented effect: " << pct(t.clean_invented, t.clean) << " (answered \"no physics is missing\": "
    << pct(t.clean_nothing, t.clean) << ")\n";
  o << "- true effects named at the true place: " << pct(t.right_place, t.named_true) << "\n";
  o << "- true parameter values (that map cleanly) with a bounded-error interval (certified equation-error PUI): "
    << pct(t.cov_bounded, t.cov) << "; inside it: " << pct(t.cov_in, t.cov_bounded) << "\n";
  o << "- inside the estimate (output-error PUI linearised at the estimate): " << pct(t.cov_estimate, t.cov)
    << "; inside the meet of the two (the reported interval before 2026-11-23): " << pct(t.cov_meet, t.cov) << "\n";
}

void write_noise_ratios(std::ostream& o, std::vector<double> x, const char* label) {
  if (x.empty()) return;
  std::sort(x.begin(), x.end());
  auto q = [&](double f) { return x[static_cast<std::size_t>(f * static_cast<double>(x.size() - 1))]; };
  int within = 0, under = 0, over = 0;
  for (double v : x) within += v >= 0.5 && v <= 2, under += v < 0.5, over += v > 2;
  o << std::setprecision(2) << "- " << label << " (" << x.size() << " outputs): median " << q(0.5) << ", 10 % " << q(0.1)
    << ", 90 % " << q(0.9) << ", lowest " << x.front() << ", highest " << x.back() << "; within a factor 2: "
    << pct(within, static_cast<int>(x.size())) << " (" << under << " under 0.5, " << over << " over 2)\n" << std::setprecision(1);
}

void write_confusion(std::ostream& o, SuiteTally& t) {
  o << "\nConfusion matrix (one-effect and clean plants; rows: true effect, columns: first named):\n\n| true \\ named |";
  for (const auto& l : t.labels) o << " " << l << " |";
  o << "\n| --- |";
  for (std::size_t i = 0; i < t.labels.size(); ++i) o << " --- |";
  o << "\n";
  for (const auto& row : t.labels) {
    if (!t.confusion.count(row)) continue;
    o << "| " << row << " |";
    for (const auto& col : t.labels) {
      const int n = t.confusion[row].count(col) ? t.confusion[row][col] : 0;
      o << " " << (n ? std::to_string(n) : "") << " |";
    }
    o << "\n";
  }
}

void write_per_effect(std::ostream& o, SuiteTally& t) {
  o << "\nPer effect (all plants; a named effect counts wherever it is named):\n\n| effect | true | named right | precision | recall |\n| --- | --- | --- | --- | --- |\n";
  std::set<std::string> effects;
  for (const auto& [e, n] : t.tp) effects.insert(e);
  for (const auto& [e, n] : t.fn) effects.insert(e);
  for (const auto& [e, n] : t.fp) effects.insert(e);
  for (const auto& e : effects) {
    const int right = t.tp.count(e) ? t.tp[e] : 0, f = t.fp.count(e) ? t.fp[e] : 0, m = t.fn.count(e) ? t.fn[e] : 0;
    o << "| " << e << " | " << right + m << " | " << right << " | " << (right + f ? pct(right, right + f) : "–") << " | "
      << (right + m ? pct(right, right + m) : "–") << " |\n";
  }
}

void write_per_family(std::ostream& o, const SuiteTally& t) {
  if (t.families.empty()) return;
  o << "\nPer family (the headline figures of each plant family):\n\n| family | one-effect, first named right | "
       "two-effect, both named | clean, invented effect |\n| --- | --- | --- | --- |\n";
  for (const auto& [family, f] : t.families)
    o << "| " << family << " | " << pct(f.one_right, f.one) << " | " << pct(f.two_both, f.two) << " | " << pct(f.clean_invented, f.clean)
      << " |\n";
}

}  // namespace

std::vector<SuitePlantResult> run_random_suite(unsigned first_seed, int count, const SuiteOptions& o) {
  return run_all(count, [&](int i) { return random_plant(first_seed + static_cast<unsigned>(i)); }, o);
}

std::vector<SuitePlantResult> run_fixed_suite(const std::string& only, const SuiteOptions& o) {
  std::vector<std::string> names;
  for (const auto& n : synthetic_plant_names())
    if (only.empty() || n == only) names.push_back(n);
  return run_all(static_cast<int>(names.size()), [&](int i) { return synthetic_plant(names[static_cast<std::size_t>(i)]); }, o);
}

std::string suite_report(const std::vector<SuitePlantResult>& results, bool table) {
  std::ostringstream o;
  o << std::fixed << std::setprecision(1);
  if (table) write_plant_table(o, results), write_equally_good(o, results);
  SuiteTally t = tally(results);
  write_summary(o, t, results.size());
  write_noise_ratios(o, t.ratios, "estimated / true noise level, final model's residual");
  write_noise_ratios(o, t.ratios_nominal, "estimated / true noise level, calibrated nominal's residual (the rules' floor)");
  write_confusion(o, t);
  write_per_effect(o, t);
  write_per_family(o, t);
  o << coverage_misses(results);
  return o.str();
}

}  // namespace sets
