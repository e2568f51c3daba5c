#include "sets/data/simulation.hpp"

#include <muParser.h>

#include <algorithm>
#include <cmath>
#include <deque>
#include <map>
#include <set>
#include <sstream>
#include <unordered_map>

#include "data/lane_expression.hpp"
#include "models/expression.hpp"
#include "sets/core/error.hpp"
#include "sets/core/printable.hpp"
#include "sets/data/intersample.hpp"

namespace sets {

Eigen::VectorXd SimulationResult::series(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return values.col(static_cast<Eigen::Index>(i));
  throw InputError("no recorded signal \"" + name + "\"");
}

double fit_percent(const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::Ref<const Eigen::VectorXd>& yhat) {
  const double den = (y.array() - y.mean()).matrix().norm();
  if (!(den > 0)) return (y - yhat).norm() == 0 ? 100.0 : -1e9;
  return 100.0 * (1.0 - (y - yhat).norm() / den);
}

namespace {

// A symbol of the model: where its value lives while expressions are evaluated.
enum class Kind { time, ts, parameter, input, state, signal, sampled, prev };

// One compiled expression. One that is a single symbol (a position's derivative `v`) is read
// from its slot: muparser's call costs more than the read.
struct Compiled {
  mu::Parser parser;
  const double* symbol = nullptr;
  double eval() { return symbol ? *symbol : parser.Eval(); }
};

struct PrevRef {
  int symbol;  // slot of x
  int lag;     // n
  int slot;    // slot of the generated variable
};

}  // namespace

struct Simulator::Impl {
  ModelFile model;
  SimulationOptions options;
  std::vector<double> time;
  double Ts = 0;
  // Slots: one double per symbol; muparser keeps pointers into `slots`, so it never reallocates.
  std::deque<double> slots;
  std::map<std::string, int> slot_of;
  std::map<int, std::string> name_of_slot;
  int t_slot = 0, ts_slot = 0;
  std::vector<int> param_slots, input_slots, state_slots, signal_slots, sampled_slots;
  std::vector<IntersampleInput> input_data;  // each input inside every sample interval
  bool inputs_move = false;                  // some input is not held (foh, bl)
  std::vector<double> initial_state;
  std::vector<Compiled> signal_expr, sampled_expr, deriv_expr;
  // The same expressions for simulations run side by side (simulate_outputs_each).
  std::vector<Lane_expression> signal_lanes, sampled_lanes, deriv_lanes;
  std::vector<int> deriv_of_state;  // derivative expression index for each state
  std::vector<PrevRef> prevs;
  std::vector<int> recorded_slots;  // inputs, states, signals, sampled
  std::vector<int> history_index;   // slot -> index in recorded_slots (or -1)
  Eigen::MatrixXd measured;
  std::vector<int> output_slots;
  // Addresses of the slots the time loop touches (the deque never moves its elements; filled
  // once every slot exists): indexing a deque costs a division per access.
  double* t_ptr = nullptr;
  std::vector<double*> param_ptr, input_ptr, state_ptr, signal_ptr, sampled_ptr, recorded_ptr, output_ptr;

  double* at(int slot) { return &slots[static_cast<std::size_t>(slot)]; }
  std::vector<double*> addresses(const std::vector<int>& of) {
    std::vector<double*> a;
    for (int s : of) a.push_back(at(s));
    return a;
  }
  void take_addresses() {
    t_ptr = at(t_slot);
    param_ptr = addresses(param_slots);
    input_ptr = addresses(input_slots);
    state_ptr = addresses(state_slots);
    signal_ptr = addresses(signal_slots);
    sampled_ptr = addresses(sampled_slots);
    recorded_ptr = addresses(recorded_slots);
    output_ptr = addresses(output_slots);
  }

  int new_slot(const std::string& name) {
    slots.push_back(0.0);
    const int s = static_cast<int>(slots.size()) - 1;
    slot_of[name] = s;
    name_of_slot[s] = name;
    return s;
  }

  void compile(Compiled& c, const std::string& text, const std::string& where) {
    mu::Parser& p = c.parser;
    // The expression layer checks the text and rewrites prev(x, n) into a generated variable,
    // filled from the history before each sample interval.
    const Checked_expression e = check_expression(
        text, [&](const std::string& n) { return is_symbol_name(n) && slot_of.count(n) > 0; },
        model.source + ": " + where);
    for (const auto& pr : e.prevs)
      if (!slot_of.count(pr.variable)) {
        const int slot = new_slot(pr.variable);
        prevs.push_back({slot_of.at(pr.symbol), pr.lag, slot});
      }
    try {
      compile_expression(p, e, [&](const std::string& n) { return &slots[static_cast<std::size_t>(slot_of.at(n))]; });
      p.Eval();  // anything muparser still objects to surfaces here, not during simulation
      if (e.prevs.empty() && e.symbols.size() == 1 && e.text == e.symbols.front()) c.symbol = at(slot_of.at(e.text));
    } catch (const mu::Parser::exception_type& err) {
      throw InputError(model.source + ": cannot parse " + where + ": \"" + printable(text, 120) +
                       "\": " + printable(err.GetMsg(), 200));
    }
  }

  // Whether a symbol has a value at sample 0 before any expression runs: inputs and states do; a
  // sampled or algebraic signal's own past there is 0 (prev()'s rule at the first sample).
  bool known_at_start(int slot) const {
    return std::find(input_slots.begin(), input_slots.end(), slot) != input_slots.end() ||
           std::find(state_slots.begin(), state_slots.end(), slot) != state_slots.end();
  }

  void eval_signals() {
    for (std::size_t i = 0; i < signal_expr.size(); ++i) *signal_ptr[i] = signal_expr[i].eval();
  }

  // Inputs at stage j (0 .. 2 substeps) of sample interval k.
  void set_inputs(std::size_t k, int j) {
    for (std::size_t i = 0; i < input_ptr.size(); ++i) *input_ptr[i] = input_data[i].at(k, j);
  }

  void derivative(const double* x, double tt, double* dx) {
    *t_ptr = tt;
    for (std::size_t i = 0; i < state_ptr.size(); ++i) *state_ptr[i] = x[i];
    eval_signals();
    for (std::size_t i = 0; i < state_ptr.size(); ++i) dx[i] = deriv_expr[static_cast<std::size_t>(deriv_of_state[i])].eval();
  }
};

namespace {
Eigen::MatrixXd take_measured(const ModelFile& m, const Recording& data) {
  Eigen::MatrixXd y(data.rows(), static_cast<Eigen::Index>(m.outputs.size()));
  for (std::size_t j = 0; j < m.outputs.size(); ++j) {
    const auto& c = data.column(m.outputs[j].second);
    for (int i = 0; i < data.rows(); ++i) y(i, static_cast<Eigen::Index>(j)) = c[static_cast<std::size_t>(i)];
  }
  return y;
}
}  // namespace

Simulator::Simulator(const ModelFile& model, const Recording& data, SimulationOptions options)
    : impl_(std::make_unique<Impl>()) {
  auto& I = *impl_;
  I.model = model;
  I.options = options;
  if (options.substeps < 1) throw InputError("substeps must be >= 1");
  const int N = data.rows();
  if (N < 2) throw InputError(data.source + ": at least two samples are needed");
  // Time.
  if (!model.time_column.empty()) {
    I.time = data.column(model.time_column);
    for (int k = 1; k < N; ++k)
      if (!(I.time[static_cast<std::size_t>(k)] > I.time[static_cast<std::size_t>(k - 1)]))
        throw InputError(data.source + ": time column \"" + model.time_column + "\" does not increase at data row " +
                         std::to_string(k + 1) + " (t = " + std::to_string(I.time[static_cast<std::size_t>(k)]) +
                         " s after " + std::to_string(I.time[static_cast<std::size_t>(k - 1)]) + " s)");
    I.Ts = (I.time.back() - I.time.front()) / (N - 1);
  } else {
    I.Ts = *model.sample_time;
    I.time.resize(static_cast<std::size_t>(N));
    for (int k = 0; k < N; ++k) I.time[static_cast<std::size_t>(k)] = k * I.Ts;
  }
  // Slots.
  I.t_slot = I.new_slot("t");
  I.ts_slot = I.new_slot("Ts");
  I.slots[static_cast<std::size_t>(I.ts_slot)] = I.Ts;
  for (const auto& p : model.parameters) {
    I.param_slots.push_back(I.new_slot(p.name));
    I.slots.back() = p.value;
  }
  for (const auto& [sym, col] : model.inputs) {
    I.input_slots.push_back(I.new_slot(sym));
    const Intersample mode = declared_intersample(model, sym);
    I.input_data.emplace_back(data.column(col), mode, options.substeps);
    I.inputs_move = I.inputs_move || mode != Intersample::zoh;
  }
  for (const auto& s : model.states) {
    I.state_slots.push_back(I.new_slot(s.name));
    I.initial_state.push_back(s.initial_value ? *s.initial_value : data.column(s.initial_column).front());
  }
  for (const auto& e : model.signals) I.signal_slots.push_back(I.new_slot(e.first));
  for (const auto& e : model.sampled) I.sampled_slots.push_back(I.new_slot(e.first));
  // Expressions (each parser gets pointers to the slots it uses).
  I.signal_expr.resize(model.signals.size());
  I.sampled_expr.resize(model.sampled.size());
  I.deriv_expr.resize(model.derivatives.size());
  for (std::size_t i = 0; i < model.signals.size(); ++i)
    I.compile(I.signal_expr[i], model.signals[i].second, "signals." + model.signals[i].first);
  for (std::size_t i = 0; i < model.sampled.size(); ++i)
    I.compile(I.sampled_expr[i], model.sampled[i].second, "sampled." + model.sampled[i].first);
  for (std::size_t i = 0; i < model.derivatives.size(); ++i)
    I.compile(I.deriv_expr[i], model.derivatives[i].second, "derivatives." + model.derivatives[i].first);
  for (const auto& s : model.states)
    for (std::size_t i = 0; i < model.derivatives.size(); ++i)
      if (model.derivatives[i].first == s.name) I.deriv_of_state.push_back(static_cast<int>(i));
  // Recorded symbols and histories for prev().
  for (int s : I.input_slots) I.recorded_slots.push_back(s);
  for (int s : I.state_slots) I.recorded_slots.push_back(s);
  for (int s : I.signal_slots) I.recorded_slots.push_back(s);
  for (int s : I.sampled_slots) I.recorded_slots.push_back(s);
  I.history_index.assign(I.slots.size(), -1);
  for (std::size_t i = 0; i < I.recorded_slots.size(); ++i) I.history_index[static_cast<std::size_t>(I.recorded_slots[i])] = static_cast<int>(i);
  for (const auto& pr : I.prevs)
    if (I.history_index[static_cast<std::size_t>(pr.symbol)] < 0)
      throw InputError(model.source + ": prev(" + I.name_of_slot[pr.symbol] +
                       ", n): only inputs, states, signals and sampled signals have a past");
  for (const auto& o : model.outputs) I.output_slots.push_back(I.slot_of.at(o.first));
  I.measured = take_measured(model, data);
  I.take_addresses();
  std::unordered_map<const double*, int> slot_at;
  for (std::size_t s = 0; s < I.slots.size(); ++s) slot_at[&I.slots[s]] = static_cast<int>(s);
  const auto slot_of = [&](const double* address) { return slot_at.at(address); };
  for (auto& c : I.signal_expr) I.signal_lanes.emplace_back(c.parser, slot_of);
  for (auto& c : I.sampled_expr) I.sampled_lanes.emplace_back(c.parser, slot_of);
  for (auto& c : I.deriv_expr) I.deriv_lanes.emplace_back(c.parser, slot_of);
}

Simulator::~Simulator() = default;

const ModelFile& Simulator::model() const { return impl_->model; }
int Simulator::samples() const { return static_cast<int>(impl_->time.size()); }
const std::vector<double>& Simulator::time() const { return impl_->time; }
double Simulator::sample_time() const { return impl_->Ts; }
const Eigen::MatrixXd& Simulator::measured() const { return impl_->measured; }
Eigen::VectorXd Simulator::parameter_values() const {
  Eigen::VectorXd p(static_cast<Eigen::Index>(impl_->model.parameters.size()));
  for (std::size_t i = 0; i < impl_->model.parameters.size(); ++i) p[static_cast<Eigen::Index>(i)] = impl_->model.parameters[i].value;
  return p;
}
std::vector<int> Simulator::free_parameters() const {
  std::vector<int> f;
  for (std::size_t i = 0; i < impl_->model.parameters.size(); ++i)
    if (!impl_->model.parameters[i].fixed) f.push_back(static_cast<int>(i));
  return f;
}
std::vector<std::string> Simulator::parameter_names() const {
  std::vector<std::string> n;
  for (const auto& p : impl_->model.parameters) n.push_back(p.name);
  return n;
}
std::vector<std::string> Simulator::output_names() const {
  std::vector<std::string> n;
  for (const auto& o : impl_->model.outputs) n.push_back(o.first);
  return n;
}
std::vector<std::string> Simulator::output_columns() const {
  std::vector<std::string> n;
  for (const auto& o : impl_->model.outputs) n.push_back(o.second);
  return n;
}

namespace {

struct Run {
  bool ok = true;
  double t_fail = 0;
  std::string state_fail;
};

// One classical RK4 substep of x over [tt, tt + h], s-th of its sample interval. x holds one state
// vector, or one value per lane and state (run_lanes): the arithmetic is elementwise either way,
// so run() and run_lanes() step through the same lines and each lane stays bit for bit run()'s.
// Moving inputs are staged at t, t + h/2 and t + h of the substep (set_inputs(2 s .. 2 s + 2)).
struct Rk4_step {
  std::vector<double> k1, k2, k3, k4, xt;
  explicit Rk4_step(std::size_t n) : k1(n), k2(n), k3(n), k4(n), xt(n) {}

  template <class Derivative, class Set_inputs>
  void operator()(std::vector<double>& x, double tt, double h, int s, bool inputs_move, Derivative&& derivative,
                  Set_inputs&& set_inputs) {
    const std::size_t n = x.size();
    if (inputs_move) set_inputs(2 * s);
    derivative(x.data(), tt, k1.data());
    for (std::size_t i = 0; i < n; ++i) xt[i] = x[i] + 0.5 * h * k1[i];
    if (inputs_move) set_inputs(2 * s + 1);
    derivative(xt.data(), tt + 0.5 * h, k2.data());
    for (std::size_t i = 0; i < n; ++i) xt[i] = x[i] + 0.5 * h * k2[i];
    derivative(xt.data(), tt + 0.5 * h, k3.data());
    for (std::size_t i = 0; i < n; ++i) xt[i] = x[i] + h * k3[i];
    if (inputs_move) set_inputs(2 * s + 2);
    derivative(xt.data(), tt + h, k4.data());
    for (std::size_t i = 0; i < n; ++i) x[i] += h / 6.0 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i]);
  }
};

}  // namespace

// Fills `outputs` (samples x outputs) and, with `record_values`, `values` (samples x recorded
// signals). `schedule` (samples x parameters, or empty for none): the parameter values held over
// each sample interval, replacing `params` from that sample on.
static Run run(Simulator::Impl& I, const Eigen::Ref<const Eigen::VectorXd>& params, Eigen::MatrixXd& outputs,
               bool record_values, Eigen::MatrixXd& values, const Eigen::Ref<const Eigen::MatrixXd>& schedule) {
  Run r;
  const int N = static_cast<int>(I.time.size());
  const std::size_t ns = I.state_slots.size();
  const std::size_t nr = I.recorded_slots.size();
  if (params.size() != static_cast<Eigen::Index>(I.param_slots.size())) throw InputError("wrong number of parameters");
  for (std::size_t i = 0; i < I.param_ptr.size(); ++i) *I.param_ptr[i] = params[static_cast<Eigen::Index>(i)];
  // The recorded symbols' past, kept only when prev() reads it.
  std::vector<double> hist(I.prevs.empty() ? 0 : static_cast<std::size_t>(N) * nr);
  std::vector<double> x(I.initial_state);
  Rk4_step step(ns);
  outputs.resize(N, static_cast<Eigen::Index>(I.output_slots.size()));
  if (record_values) values.resize(N, static_cast<Eigen::Index>(nr));
  const bool scheduled = schedule.rows() > 0;
  for (int k = 0; k < N; ++k) {
    const double tk = I.time[static_cast<std::size_t>(k)];
    *I.t_ptr = tk;
    if (scheduled)
      for (std::size_t i = 0; i < I.param_ptr.size(); ++i) *I.param_ptr[i] = schedule(k, static_cast<Eigen::Index>(i));
    for (std::size_t i = 0; i < I.input_ptr.size(); ++i) *I.input_ptr[i] = I.input_data[i].at(static_cast<std::size_t>(k), 0);
    for (std::size_t i = 0; i < ns; ++i) *I.state_ptr[i] = x[i];
    // prev() values: sample k - n, or sample 0 when there is none yet.
    for (const auto& pr : I.prevs) {
      const int h = I.history_index[static_cast<std::size_t>(pr.symbol)];
      const int kk = std::max(0, k - pr.lag);
      double v;
      if (kk < k) {
        v = hist[static_cast<std::size_t>(kk) * nr + static_cast<std::size_t>(h)];
      } else {
        v = I.slots[static_cast<std::size_t>(pr.symbol)];
        if (!I.known_at_start(pr.symbol)) v = 0.0;
      }
      I.slots[static_cast<std::size_t>(pr.slot)] = v;
    }
    I.eval_signals();
    for (std::size_t i = 0; i < I.sampled_expr.size(); ++i) *I.sampled_ptr[i] = I.sampled_expr[i].eval();
    I.eval_signals();  // signals may use sampled values
    if (!hist.empty())
      for (std::size_t i = 0; i < nr; ++i) hist[static_cast<std::size_t>(k) * nr + i] = *I.recorded_ptr[i];
    for (std::size_t j = 0; j < I.output_ptr.size(); ++j) outputs(k, static_cast<Eigen::Index>(j)) = *I.output_ptr[j];
    if (record_values)
      for (std::size_t i = 0; i < nr; ++i) values(k, static_cast<Eigen::Index>(i)) = *I.recorded_ptr[i];
    if (k + 1 == N) break;
    const double h = (I.time[static_cast<std::size_t>(k + 1)] - tk) / I.options.substeps;
    double tt = tk;
    const auto kk = static_cast<std::size_t>(k);
    const auto derivative = [&I](const double* xs, double t, double* dx) { I.derivative(xs, t, dx); };
    // Stage inputs: u at t, t + h/2, t + h of the substep as each input's intersample mode gives them.
    const auto stage_inputs = [&I, kk](int j) { I.set_inputs(kk, j); };
    for (int s = 0; s < I.options.substeps; ++s) {
      step(x, tt, h, s, I.inputs_move, derivative, stage_inputs);
      tt += h;
      for (std::size_t i = 0; i < ns; ++i)
        if (!std::isfinite(x[i]) || std::abs(x[i]) > 1e150) {
          r.ok = false;
          r.t_fail = tt;
          r.state_fail = I.model.states[i].name;
          return r;
        }
    }
  }
  if (!outputs.allFinite()) {
    for (int k = 0; k < N; ++k)
      if (!outputs.row(k).allFinite()) {
        r.ok = false;
        r.t_fail = I.time[static_cast<std::size_t>(k)];
        r.state_fail = "an output";
        return r;
      }
  }
  return r;
}

// run() for each column of `params` at once, its outputs only: the same steps in the same order,
// each lane's arithmetic as run()'s, so each lane's outputs are bit for bit those of run() with its
// column. A lane that blows up is marked and carried on with the others. Slots start as run()
// would find them and end as the last lane leaves them (a signal that reads a later one reads the
// value left by the run before, as in run()). `schedules` (one per lane, or empty for none): as
// run()'s schedule, lane by lane.
static void run_lanes(Simulator::Impl& I, const Eigen::Ref<const Eigen::MatrixXd>& params,
                      const std::vector<Eigen::MatrixXd>& schedules, std::vector<Eigen::MatrixXd>& outputs,
                      std::vector<bool>& ok) {
  const int N = static_cast<int>(I.time.size());
  const auto L = static_cast<std::size_t>(params.cols());
  const int lanes = static_cast<int>(L);
  const std::size_t ns = I.state_slots.size();
  std::vector<double> v(I.slots.size() * L), tmp(L);
  for (std::size_t s = 0; s < I.slots.size(); ++s) std::fill_n(v.begin() + static_cast<std::ptrdiff_t>(s * L), L, I.slots[s]);
  const auto lane = [&](int slot) { return v.data() + static_cast<std::size_t>(slot) * L; };
  for (std::size_t i = 0; i < I.param_slots.size(); ++i)
    for (std::size_t l = 0; l < L; ++l) lane(I.param_slots[i])[l] = params(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(l));
  const auto fill = [&](int slot, double value) { std::fill_n(lane(slot), L, value); };
  const auto set_inputs = [&](std::size_t k, int j) {
    for (std::size_t i = 0; i < I.input_slots.size(); ++i) fill(I.input_slots[i], I.input_data[i].at(k, j));
  };
  const auto set_states = [&](const double* xs) {
    for (std::size_t i = 0; i < ns; ++i) std::copy_n(xs + i * L, L, lane(I.state_slots[i]));
  };
  const auto eval_into = [&](const Lane_expression& e, int slot) {
    e.eval(v.data(), lanes, tmp.data());  // every lane read before any is written, as run() does
    std::copy(tmp.begin(), tmp.end(), lane(slot));
  };
  const auto eval_signals = [&] {
    for (std::size_t i = 0; i < I.signal_lanes.size(); ++i) eval_into(I.signal_lanes[i], I.signal_slots[i]);
  };
  const auto derivative = [&](const double* xs, double tt, double* dx) {
    fill(I.t_slot, tt);
    set_states(xs);
    eval_signals();
    for (std::size_t i = 0; i < ns; ++i) I.deriv_lanes[static_cast<std::size_t>(I.deriv_of_state[i])].eval(v.data(), lanes, dx + i * L);
  };
  // The recorded symbols' past, kept only when prev() reads it: sample, symbol, lane.
  const std::size_t nr = I.recorded_slots.size();
  std::vector<double> hist(I.prevs.empty() ? 0 : static_cast<std::size_t>(N) * nr * L);
  const auto set_prevs = [&](int k) {  // run()'s rule: sample k - n, or sample 0 when there is none yet
    for (const auto& pr : I.prevs) {
      const auto h = static_cast<std::size_t>(I.history_index[static_cast<std::size_t>(pr.symbol)]);
      const int kk = std::max(0, k - pr.lag);
      if (kk < k) {
        std::copy_n(hist.begin() + static_cast<std::ptrdiff_t>((static_cast<std::size_t>(kk) * nr + h) * L), L, lane(pr.slot));
        continue;
      }
      if (I.known_at_start(pr.symbol)) std::copy_n(lane(pr.symbol), L, lane(pr.slot));
      else fill(pr.slot, 0.0);
    }
  };
  std::vector<double> x(ns * L);
  Rk4_step step(ns * L);
  for (std::size_t i = 0; i < ns; ++i) std::fill_n(x.begin() + static_cast<std::ptrdiff_t>(i * L), L, I.initial_state[i]);
  outputs.assign(L, Eigen::MatrixXd(N, static_cast<Eigen::Index>(I.output_slots.size())));
  ok.assign(L, true);
  std::size_t live = L;
  for (int k = 0; k < N && live > 0; ++k) {
    const double tk = I.time[static_cast<std::size_t>(k)];
    fill(I.t_slot, tk);
    if (!schedules.empty())
      for (std::size_t i = 0; i < I.param_slots.size(); ++i)
        for (std::size_t l = 0; l < L; ++l) lane(I.param_slots[i])[l] = schedules[l](k, static_cast<Eigen::Index>(i));
    set_inputs(static_cast<std::size_t>(k), 0);
    set_states(x.data());
    set_prevs(k);
    eval_signals();
    for (std::size_t i = 0; i < I.sampled_lanes.size(); ++i) eval_into(I.sampled_lanes[i], I.sampled_slots[i]);
    eval_signals();  // signals may use sampled values
    if (!hist.empty())
      for (std::size_t i = 0; i < nr; ++i)
        std::copy_n(lane(I.recorded_slots[i]), L, hist.begin() + static_cast<std::ptrdiff_t>((static_cast<std::size_t>(k) * nr + i) * L));
    for (std::size_t j = 0; j < I.output_slots.size(); ++j)
      for (std::size_t l = 0; l < L; ++l) outputs[l](k, static_cast<Eigen::Index>(j)) = lane(I.output_slots[j])[l];
    if (k + 1 == N) break;
    const double h = (I.time[static_cast<std::size_t>(k + 1)] - tk) / I.options.substeps;
    double tt = tk;
    const auto kk = static_cast<std::size_t>(k);
    const auto stage_inputs = [&set_inputs, kk](int j) { set_inputs(kk, j); };
    for (int s = 0; s < I.options.substeps && live > 0; ++s) {
      step(x, tt, h, s, I.inputs_move, derivative, stage_inputs);
      tt += h;
      for (std::size_t i = 0; i < ns * L; ++i)
        if (ok[i % L] && (!std::isfinite(x[i]) || std::abs(x[i]) > 1e150)) {
          ok[i % L] = false;
          --live;
        }
    }
  }
  for (std::size_t l = 0; l < L; ++l) ok[l] = ok[l] && outputs[l].allFinite();
  for (std::size_t s = 0; s < I.slots.size(); ++s) I.slots[s] = v[s * L + L - 1];
}

SimulationResult Simulator::simulate(const Eigen::Ref<const Eigen::VectorXd>& parameters) const {
  SimulationResult res;
  for (int s : impl_->recorded_slots) res.names.push_back(impl_->name_of_slot.at(s));
  Run r;
  try {
    r = run(*impl_, parameters, res.outputs, true, res.values, Eigen::MatrixXd());
  } catch (const mu::Parser::exception_type& e) {
    throw NumericalError(impl_->model.source + ": expression evaluation failed: " + e.GetMsg());
  }
  if (!r.ok) {
    std::ostringstream os;
    os << impl_->model.source << ": the simulation blew up at t = " << r.t_fail << " s (" << r.state_fail
       << " is no longer finite)";
    throw NumericalError(os.str());
  }
  return res;
}

bool Simulator::simulate_outputs(const Eigen::Ref<const Eigen::VectorXd>& parameters, Eigen::MatrixXd& outputs) const {
  try {
    Eigen::MatrixXd unused;
    return run(*impl_, parameters, outputs, false, unused, Eigen::MatrixXd()).ok;
  } catch (const mu::Parser::exception_type&) {
    return false;
  }
}

// The schedule's size, checked before a run.
static void check_schedule(const Simulator::Impl& I, const Eigen::Ref<const Eigen::MatrixXd>& schedule) {
  const auto samples = static_cast<Eigen::Index>(I.time.size());
  if (schedule.rows() != samples || schedule.cols() != static_cast<Eigen::Index>(I.param_slots.size()))
    throw InputError("parameter schedule is " + std::to_string(schedule.rows()) + " x " + std::to_string(schedule.cols()) +
                     ", expected samples x parameters = " + std::to_string(samples) + " x " +
                     std::to_string(I.param_slots.size()));
}

bool Simulator::simulate_outputs_scheduled(const Eigen::Ref<const Eigen::MatrixXd>& schedule,
                                           Eigen::MatrixXd& outputs) const {
  check_schedule(*impl_, schedule);
  try {
    Eigen::MatrixXd unused;
    return run(*impl_, schedule.row(0).transpose(), outputs, false, unused, schedule).ok;
  } catch (const mu::Parser::exception_type&) {
    return false;
  }
}

// Runs `runs` side by side (run_lanes); when muparser throws, each run alone by `one`, so that
// only the run that throws fails, as it would alone.
template <class One>
static void side_by_side(Simulator::Impl& I, const Eigen::Ref<const Eigen::MatrixXd>& params,
                         const std::vector<Eigen::MatrixXd>& schedules, std::vector<Eigen::MatrixXd>& outputs,
                         std::vector<bool>& ok, const One& one) {
  const auto one_by_one = [&] {
    outputs.assign(static_cast<std::size_t>(params.cols()), Eigen::MatrixXd());
    ok.assign(outputs.size(), false);
    for (std::size_t l = 0; l < outputs.size(); ++l) ok[l] = one(l, outputs[l]);
  };
  if (params.cols() < 2) return one_by_one();
  try {
    run_lanes(I, params, schedules, outputs, ok);
  } catch (const mu::Parser::exception_type&) {
    one_by_one();
  }
}

void Simulator::simulate_outputs_each(const Eigen::Ref<const Eigen::MatrixXd>& parameters,
                                      std::vector<Eigen::MatrixXd>& outputs, std::vector<bool>& ok) const {
  if (parameters.rows() != static_cast<Eigen::Index>(impl_->param_slots.size())) throw InputError("wrong number of parameters");
  side_by_side(*impl_, parameters, {}, outputs, ok, [&](std::size_t l, Eigen::MatrixXd& y) {
    return simulate_outputs(parameters.col(static_cast<Eigen::Index>(l)), y);
  });
}

void Simulator::simulate_outputs_scheduled_each(const std::vector<Eigen::MatrixXd>& schedules,
                                                std::vector<Eigen::MatrixXd>& outputs, std::vector<bool>& ok) const {
  Eigen::MatrixXd first(impl_->param_slots.size(), schedules.size());
  for (std::size_t l = 0; l < schedules.size(); ++l) {
    check_schedule(*impl_, schedules[l]);
    first.col(static_cast<Eigen::Index>(l)) = schedules[l].row(0).transpose();
  }
  side_by_side(*impl_, first, schedules, outputs, ok,
               [&](std::size_t l, Eigen::MatrixXd& y) { return simulate_outputs_scheduled(schedules[l], y); });
}

void check_model(const ModelFile& model, const Recording& data) { Simulator s(model, data, {1}); }

}  // namespace sets
