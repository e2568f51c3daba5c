// The soundness campaign: pui() on random bounded-error regressions whose true parameter lies in
// the feasible set by construction (sets/examples/bounded_error_regression.hpp), with figures
// per kind: false "the data falsify the model" (must be 0), true parameter outside a PUI marked
// guaranteed (must be 0), undecided verdicts, numerical failures, time.
//
//   ./build/bench/soundness_campaign_bench                       # seeds 1..10000
//   ./build/bench/soundness_campaign_bench --seeds 1 500 --threads 2 --list-failures
//   ./build/bench/soundness_campaign_bench --kind badly-scaled --list-failures   # one kind only
//   ./build/bench/soundness_campaign_bench --kind errors-in-variables --orthants remark2
//
// The problems' own options search all orthants for interval regressors; --orthants remark2
// runs them with the default Remark-2 search instead (it must give the same verdicts).
//
// Exit code 1 if any false empty verdict or guaranteed miss occurred (so it can gate a run).
// A fixed-seed slice runs in the test suite (tests/examples/bounded_error_regression_test.cpp).

#include <algorithm>
#include <array>
#include <atomic>
#include <cctype>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "sets/examples/bounded_error_regression.hpp"
#include "sets/numeric/worker_threads.hpp"

namespace {

struct Tally {
  int problems = 0, false_empty = 0, guaranteed_miss = 0, miss = 0, consistent = 0, unknown = 0,
      numerical = 0, not_guaranteed = 0, infinite = 0;
  std::vector<double> seconds;
  double lps = 0;
  void add(const sets::SoundnessOutcome& o) {
    ++problems;
    false_empty += o.false_empty();
    guaranteed_miss += o.guaranteed_miss();
    miss += !o.numerical_error && !o.false_empty() && !o.theta_in_box;
    consistent += o.verdict == sets::Falsified::no;
    unknown += !o.numerical_error && o.verdict == sets::Falsified::unknown;
    numerical += o.numerical_error;
    not_guaranteed += !o.numerical_error && !o.guaranteed;
    infinite += !o.numerical_error && !o.false_empty() && !o.box_finite;
    seconds.push_back(o.seconds);
    lps += o.lp_solves;
  }
  double median_ms() {
    if (seconds.empty()) return 0;
    std::nth_element(seconds.begin(), seconds.begin() + static_cast<std::ptrdiff_t>(seconds.size() / 2), seconds.end());
    return 1e3 * seconds[seconds.size() / 2];
  }
  double total_s() const {
    double s = 0;
    for (double x : seconds) s += x;
    return s;
  }
};

[[noreturn]] void usage(const char* msg) {
  (msg ? std::cerr : std::cout)
      << (msg ? std::string("soundness_campaign_bench: ") + msg + "\n" : std::string())
      << "usage: soundness_campaign_bench [--seeds FIRST LAST] [--threads T] [--kind KIND] [--orthants O]\n"
      << "                                [--list-failures]\n"
      << "  KIND: normal, badly-scaled, near-collinear, errors-in-variables, tiny-n (default: all)\n"
      << "  O: as generated (default: all orthants for interval regressors) or remark2\n";
  std::exit(msg ? 1 : 0);
}

unsigned long parse_count(const char* s, const char* flag) {
  char* end = nullptr;
  const unsigned long v = std::strtoul(s, &end, 10);
  if (end == s || *end != '\0' || v == 0) usage((std::string(flag) + " needs a positive integer").c_str());
  return v;
}

}  // namespace

int main(int argc, char** argv) {
  unsigned long first = 1, last = 10000, threads = 1;
  bool list = false, remark2 = false;
  int kind = -1;  // all kinds
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--seeds") && i + 2 < argc) {
      first = parse_count(argv[++i], "--seeds");
      last = parse_count(argv[++i], "--seeds");
    } else if (!std::strcmp(argv[i], "--threads") && i + 1 < argc) {
      threads = parse_count(argv[++i], "--threads");
    } else if (!std::strcmp(argv[i], "--kind") && i + 1 < argc) {
      const std::string want = argv[++i];
      for (int k = 0; k < sets::regression_kind_count; ++k) {
        std::string name = sets::to_string(static_cast<sets::RegressionKind>(k));
        std::replace(name.begin(), name.end(), ' ', '-');
        std::transform(name.begin(), name.end(), name.begin(), [](unsigned char c) { return std::tolower(c); });
        if (name == want) kind = k;
      }
      if (kind < 0) usage(("--kind: unknown kind '" + want + "'").c_str());
    } else if (!std::strcmp(argv[i], "--orthants") && i + 1 < argc) {
      const std::string want = argv[++i];
      if (want != "remark2" && want != "all") usage(("--orthants: expected remark2 or all, got '" + want + "'").c_str());
      remark2 = want == "remark2";
    } else if (!std::strcmp(argv[i], "--help") || !std::strcmp(argv[i], "-h")) {
      usage(nullptr);
    } else if (!std::strcmp(argv[i], "--list-failures")) {
      list = true;
    } else {
      usage((std::string("unknown or incomplete argument '") + argv[i] + "'").c_str());
    }
  }
  if (last < first) usage("--seeds: LAST < FIRST");
  std::vector<unsigned long> seeds;
  for (unsigned long s = first; s <= last; ++s)
    if (kind < 0 || static_cast<int>(sets::regression_kind_of_seed(s)) == kind) seeds.push_back(s);
  std::vector<sets::SoundnessOutcome> out(seeds.size());
  std::atomic<std::size_t> next{0};
  std::atomic<unsigned long> done{0};
  sets::run_worker_threads(static_cast<int>(threads), [&] {
    for (std::size_t i; (i = next++) < seeds.size();) {
      sets::BoundedErrorRegression problem = sets::bounded_error_regression(seeds[i]);
      if (remark2) problem.options.orthants = sets::OrthantSelection::remark2;
      out[i] = sets::run_soundness_problem(problem);
      const unsigned long k = ++done;
      if (k % 1000 == 0) std::cerr << "  " << k << " / " << out.size() << " problems\n";
    }
  });

  std::array<Tally, sets::regression_kind_count + 1> tally;
  for (const auto& o : out) {
    tally[static_cast<std::size_t>(o.kind)].add(o);
    tally.back().add(o);
    if (list && (o.false_empty() || !o.theta_in_box || o.numerical_error || o.verdict != sets::Falsified::no))
      std::cout << "seed " << o.seed << " (" << sets::to_string(o.kind) << ", p = " << o.parameters
                << ", N = " << o.samples << "): verdict " << sets::to_string(o.verdict)
                << (o.guaranteed ? ", guaranteed" : ", not guaranteed") << (o.theta_in_box ? "" : ", theta outside")
                << (o.numerical_error ? ", NumericalError: " + o.error : "") << '\n';
  }
  std::printf("\nseeds %lu..%lu%s%s, %lu thread(s)\n", first, last, kind < 0 ? "" : ", kind ",
              kind < 0 ? "" : sets::to_string(static_cast<sets::RegressionKind>(kind)), threads);
  std::printf("%-20s %8s %7s %8s %7s %8s %8s %8s %7s %8s %9s %9s\n", "kind", "problems", "false", "theta out",
              "theta", "unknown", "certif.", "Numeric.", "not", "infinite", "median", "total");
  std::printf("%-20s %8s %7s %8s %7s %8s %8s %8s %7s %8s %9s %9s\n", "", "", "empty", "guarant.", "out",
              "verdict", "consist.", "Error", "guar.", "box", "ms", "s");
  for (std::size_t k = 0; k < tally.size(); ++k) {
    Tally& t = tally[k];
    const char* name = k < sets::regression_kind_count ? sets::to_string(static_cast<sets::RegressionKind>(k)) : "all";
    std::printf("%-20s %8d %7d %8d %7d %8d %8d %8d %7d %8d %9.2f %9.1f\n", name, t.problems, t.false_empty,
                t.guaranteed_miss, t.miss, t.unknown, t.consistent, t.numerical, t.not_guaranteed, t.infinite,
                t.median_ms(), t.total_s());
  }
  return tally.back().false_empty == 0 && tally.back().guaranteed_miss == 0 ? 0 : 1;
}
