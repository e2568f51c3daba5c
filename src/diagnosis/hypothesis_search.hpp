#pragma once
// Stage 3 of the diagnosis (hypotheses.cpp) in parts: what its files share — a refined
// hypothesis (Trial), a round's state (Round), and the functions one part calls in another.

#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "diagnosis/stages.hpp"
#include "sets/diagnosis/screening.hpp"

namespace sets::diagnosis_stage {

using Scales = std::vector<std::pair<std::string, double>>;
inline const double kNaN = std::numeric_limits<double>::quiet_NaN();
inline const double inf = std::numeric_limits<double>::infinity();

struct Trial {
  Candidate cand;
  ModelFile model;  // calibrated
  double cost = 1e300, cost_val = kNaN;
  double cost_neutral = kNaN, cost_neutral_val = kNaN;
  std::vector<double> costs, costs_neutral;  // cost and cost_neutral per output (estimation)
  ModelFile neutral_model;  // the calibrated model with the effect switched off
  std::vector<double> part_neutral;  // two effects at once: the cost with each one switched off
  bool ok = false;
  double screening_gain = 0;
  std::vector<RuleCheck> rules;
  bool accepted = false;
  std::string not_beyond;  // passed against the current model, not against this special case of it
  int substeps = 0;  // RK4 substeps of its refinement when finer than the screening's (0: the screening's)
};

// One hypothesis to refine: its candidate and the starts of its output-error calibration.
struct ToRefine {
  const Candidate* cand;
  std::vector<Eigen::VectorXd> starts;
  int substeps = 0;  // 0: the screening's
};

using Fixed = std::vector<std::pair<std::string, double>>;

// ---- one round of the search, stage by stage

// What one round of the greedy search carries from stage to stage.
struct Round {
  int index = 0;
  SimulationResult current_simulation;  // of the current model (the special cases are built on it)
  Screening screening;
  std::vector<const ScreenedHypothesis*> list;  // the shortlist, refined
  std::vector<Trial> trials;                    // [0]: the null hypothesis; [i]: list[i - 1]
  double cost_cur = 1e300, cost_cur_val = kNaN;  // the baseline every hypothesis must beat
  std::vector<double> costs_cur;                 // its cost per output (estimation)
  std::vector<std::size_t> ok;                   // trials that pass every rule
  std::map<std::size_t, std::string> beats;      // a richer law kept: the special cases it beat
  std::deque<ScreenedHypothesis> built;          // hypotheses the round built itself (list points here)
  Screening at_file;                             // round 1 (nominal far, or named nothing): the screening at the file's values
  std::map<const ScreenedHypothesis*, std::vector<Eigen::VectorXd>> from_file;  // listed: starts from it too
};

// hypotheses.cpp
// The round's shortlist refined by output error beside the null hypothesis (the current model
// calibrated again); sets the baseline, and h.current takes the null's optimum.
void refine_round(const Context& c, HypothesisSearch& h, Round& r, Diagnosis& d);

// refine_trials.cpp
// `m` with every parameter it leaves free at `file`'s value where the file declares it: the start
// the nominal's own calibration had, before that calibration could absorb a missing effect.
ModelFile at_file_values(ModelFile m, const ModelFile& file);
std::vector<Trial> refine(const Context& c, const std::vector<ToRefine>& hypotheses, const Scales& known);
// Every whole number of samples between the delay grid's neighbours of n0 (the grid is coarse;
// n0 need not be on it), below a tenth of the record's `samples`.
std::vector<int> delays_around(int n0, int samples);
Candidate best_delay(const Context& c, const ModelFile& current, const Candidate& chosen, const std::vector<double>& bound);

// special_cases.cpp
std::vector<Candidate> parts_of(const Candidate& c);
// The single hypothesis of `part` (a pair's member) in the screening, if it was screened alone.
const ScreenedHypothesis* screened_alone(const Screening& s, const Candidate& part);
bool nests(const Candidate& general, const Candidate& special, Fixed* fixed = nullptr);
std::optional<Candidate> pair_on(const Context& c, const Candidate& first,
                                 const std::function<const Candidate*(const std::vector<Candidate>&)>& second_of);
std::vector<Candidate> missing_special_cases(const Context& c, const ModelFile& current, const SimulationResult& sim,
                                             const Candidate& general, const std::vector<const Candidate*>& calibrated);
ModelFile mapped_by_role(const Candidate& target, const Candidate& source, const ModelFile& source_model);
std::vector<Eigen::VectorXd> starts_at_special_case(const Candidate& richer, const Trial& special);
std::optional<Eigen::VectorXd> switched_on_start(const Context& c, const Candidate& richer, const Trial& special);
std::optional<Eigen::VectorXd> pair_switched_on_start(const Context& c, const Candidate& richer, const Trial& special,
                                                      std::size_t j);
std::vector<Eigen::VectorXd> starts_from_special_case(const Context& c, const Candidate& richer, const Trial& special);

// refine_again.cpp
void continue_from_special_cases(const Context& c, const HypothesisSearch& h, Round& r);
bool refine_worse_than_the_baseline(const Context& c, const HypothesisSearch& h, Round& r);
void refine_members_of_nil_pairs(const Context& c, const HypothesisSearch& h, double min_own_term, Round& r, Diagnosis& d);
void refine_richer_pairs(const Context& c, const HypothesisSearch& h, double min_own_term, Round& r, Diagnosis& d);
void refine_richer_below_special_cases(const Context& c, const HypothesisSearch& h, Round& r);
void refine_delay_numbers(const Context& c, const HypothesisSearch& h, const std::vector<double>& bound, Round& r);

// refine_at_law_step.cpp
void refine_at_the_step_laws_need(const Context& c, const HypothesisSearch& h, Round& r);
int step_after_pick(const Context& c, const Trial& t);

// upgrade_named_laws.cpp
// After the rounds, each named special case of a richer law (Coulomb friction; Coulomb friction +
// an offset at one place) judged again against its richer laws beside every other effect named;
// replaced in h and d when the round's rules pick the richer law.
void upgrade_named_laws(const Context& c, HypothesisSearch& h, const NoiseFloor& noise, const AcceptanceRules& rules, Diagnosis& d);

// judge_round.cpp
void judge_round(const Context& c, const HypothesisSearch& h, const NoiseFloor& noise, const AcceptanceRules& rules, Round& r);
void say_round(const Context& c, const Round& r);
std::pair<std::size_t, std::size_t> pick_sparsest(const Context& c, const Round& r);
std::vector<EquallyGood> equally_good(const Round& r, const NoiseFloor& noise, const AcceptanceRules& rules, std::size_t a);
void record_pick(const Context& c, const Round& r, std::size_t pick, std::size_t best, std::vector<EquallyGood> alike,
                 HypothesisSearch& h, std::vector<std::string>& chosen, Diagnosis& d);

}  // namespace sets::diagnosis_stage
