// libFuzzer harness: the expression layer (our checker, prev(x, n), muparser) through the
// Simulator. Input lines 1-3 are the right-hand side of x' , the signal s and the sampled signal z
// of a small model over symbols t, Ts, a, b, u, x, v, s, z; a missing line is "0". The model is
// compiled and simulated over four samples.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_support.hpp"
#include "sets/data/recording.hpp"
#include "sets/data/simulation.hpp"
#include "sets/models/model_file.hpp"

namespace {

const sets::Recording& recording() {
  static const sets::Recording r = [] {
    sets::Recording d;
    d.source = "fuzz.csv";
    d.add("u", {1.0, -2.0, 0.5, 3.0});
    d.add("y", {0.0, 0.1, 0.2, 0.3});
    return d;
  }();
  return r;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<std::string> lines(1);
  for (std::size_t i = 0; i < size; ++i) {
    if (data[i] == '\n' && lines.size() < 3) lines.emplace_back();
    else lines.back() += static_cast<char>(data[i]);
  }
  lines.resize(3);
  for (auto& l : lines)
    if (l.empty()) l = "0";
  sets::ModelFile m;
  m.source = "fuzz.json";
  m.sample_time = 0.1;
  m.inputs = {{"u", "u"}};
  m.parameters = {{"a", 0.5, false}, {"b", -2.0, true}};
  m.states = {{"x", 0.0, ""}, {"v", 1.0, ""}};
  m.signals = {{"s", lines[1]}};
  m.sampled = {{"z", lines[2]}};
  m.derivatives = {{"x", lines[0]}, {"v", "-v"}};
  m.outputs = {{"x", "y"}};
  sets::fuzz::expect_documented_errors(
      [&] {
        sets::Simulator sim(m, recording(), {2});
        (void)sim.simulate(sim.parameter_values());
      },
      "fuzz.json", /*numerical_ok=*/true);
  return 0;
}
