#pragma once
// The JSON model file (format version 1): a continuous-time model written by an engineer, with the
// recording columns it is compared against. See docs/model-format.md.

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sets/core/atomic_file.hpp"

namespace sets {

struct ModelParameter {
  std::string name;
  double value = 0;
  bool fixed = false;
  double min = -1e300;  // no bound when +-1e300
  double max = 1e300;
};

struct ModelState {
  std::string name;
  std::optional<double> initial_value;  // a number ...
  std::string initial_column;           // ... or the first sample of this column
};

/// An ordered list of name -> text (the order of the file is kept: signals may use earlier ones).
using NamedTexts = std::vector<std::pair<std::string, std::string>>;

struct ModelFile {
  std::string name;
  std::string time_column;             // "time": column with time in s ...
  std::optional<double> sample_time;   // ... or "sample_time" in s
  NamedTexts inputs;                   // symbol -> column
  NamedTexts intersample;              // input symbol -> "zoh" | "foh" | "bl" (optional; absent: zoh)
  std::vector<ModelParameter> parameters;
  std::vector<ModelState> states;
  NamedTexts signals;                  // symbol -> expression, evaluated continuously
  NamedTexts sampled;                  // symbol -> expression, evaluated at samples and held
  NamedTexts derivatives;              // state -> expression of its time derivative
  NamedTexts outputs;                  // model symbol -> column it is compared with
  NamedTexts units;                    // optional: symbol or column -> unit, e.g. "q_meas": "m"
  std::string source = "<model>";      // file name for messages

  const ModelParameter* parameter(const std::string& n) const;
  ModelParameter* parameter(const std::string& n);
  const std::string* derivative(const std::string& state) const;
  std::string* derivative(const std::string& state);
  bool has_symbol(const std::string& n) const;  // any defined name (t, Ts included)
  /// Unit of a symbol or of a column the model reads ("" when the file gives none; "s" for the
  /// time). An output column without its own entry takes its model symbol's unit and vice versa.
  std::string unit(const std::string& name) const;
};

/// Parses format version 1. Malformed JSON -> InputError with line and column; wrong or missing
/// fields -> InputError naming the field.
ModelFile parse_model(const std::string& text, const std::string& source = "<model>");
ModelFile load_model_file(const std::string& path);
/// Writes the same format (readable back by parse_model).
std::string to_json_text(const ModelFile& model);
/// Writes completely or not at all (temporary name, then rename).
void save_model_file(const ModelFile& model, const std::string& path);


}  // namespace sets
