#include "sets/models/model_file.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/json_text.hpp"
#include "models/expression.hpp"
#include "sets/core/error.hpp"
#include "sets/core/printable.hpp"

namespace sets {

using ojson = nlohmann::ordered_json;

const ModelParameter* ModelFile::parameter(const std::string& n) const {
  for (const auto& p : parameters)
    if (p.name == n) return &p;
  return nullptr;
}
ModelParameter* ModelFile::parameter(const std::string& n) {
  for (auto& p : parameters)
    if (p.name == n) return &p;
  return nullptr;
}
const std::string* ModelFile::derivative(const std::string& state) const {
  for (const auto& d : derivatives)
    if (d.first == state) return &d.second;
  return nullptr;
}
std::string* ModelFile::derivative(const std::string& state) {
  for (auto& d : derivatives)
    if (d.first == state) return &d.second;
  return nullptr;
}
bool ModelFile::has_symbol(const std::string& n) const {
  if (n == "t" || n == "Ts" || parameter(n)) return true;
  for (const auto* list : {&inputs, &signals, &sampled})
    for (const auto& e : *list)
      if (e.first == n) return true;
  for (const auto& s : states)
    if (s.name == n) return true;
  return false;
}

std::string ModelFile::unit(const std::string& name) const {
  auto find = [&](const std::string& n) -> const std::string* {
    for (const auto& [k, u] : units)
      if (k == n) return &u;
    return nullptr;
  };
  if (const auto* u = find(name)) return *u;
  for (const auto& [symbol, column] : outputs) {
    if (column == name)
      if (const auto* u = find(symbol)) return *u;
    if (symbol == name)
      if (const auto* u = find(column)) return *u;
  }
  return name == "t" || (!time_column.empty() && name == time_column) ? "s" : "";
}

namespace {

[[noreturn]] void fail(const std::string& source, const std::string& what) {
  throw InputError(source + ": " + what);
}

NamedTexts read_texts(const ojson& j, const char* key, const std::string& source, bool required) {
  NamedTexts out;
  if (!j.contains(key)) {
    if (required) fail(source, std::string("missing field \"") + key + "\"");
    return out;
  }
  const auto& o = j.at(key);
  if (!o.is_object()) fail(source, std::string("field \"") + key + "\" must be an object");
  for (auto it = o.begin(); it != o.end(); ++it) {
    if (!it.value().is_string())
      fail(source, std::string("field \"") + key + "." + printable(it.key(), 100) + "\" must be a string");
    out.emplace_back(it.key(), it.value().get<std::string>());
  }
  return out;
}

double number(const ojson& v, const std::string& source, const std::string& field) {
  if (!v.is_number()) fail(source, "field \"" + field + "\" must be a number");
  return v.get<double>();
}

// "units": {"name": "unit", ...}; a name is a symbol of the model or a column it reads.
void read_units(const ojson& j, ModelFile& m) {
  m.units = read_texts(j, "units", m.source, false);
  for (const auto& [name, unit] : m.units) {
    bool known = m.has_symbol(name) || name == m.time_column;
    for (const auto* list : {&m.inputs, &m.outputs})
      for (const auto& e : *list) known = known || e.second == name;
    for (const auto& s : m.states) known = known || s.initial_column == name;
    if (!known)
      fail(m.source, "\"units." + printable(name, 100) + "\" is neither a symbol of the model nor a column it reads");
    // Units end up in figure scripts and labels: one short line of printable text.
    const bool printable_text = unit.size() <= 40 && std::none_of(unit.begin(), unit.end(), [](char c) {
      return static_cast<unsigned char>(c) < 0x20 || c == 0x7f;
    });
    if (!printable_text)
      fail(m.source, "\"units." + printable(name, 100) + "\" must be at most 40 characters without control characters");
  }
}

void check_known_fields(const ojson& j, const std::string& source) {
  static const char* known[] = {"name",    "time",    "sample_time", "inputs",      "parameters",
                                "states",  "signals", "sampled",     "derivatives", "outputs",
                                "format_version", "intersample", "units"};
  for (auto it = j.begin(); it != j.end(); ++it) {
    bool ok = false;
    for (const char* k : known) ok = ok || it.key() == k;
    if (!ok) fail(source, "unknown field \"" + printable(it.key(), 100) + "\"");
  }
  if (j.contains("format_version") && number(j["format_version"], source, "format_version") != 1)
    fail(source, "unsupported format_version (this reader knows version 1)");
}

// "name", and the time base: a time column, a sample time, or both.
void read_name_and_time(const ojson& j, ModelFile& m) {
  const std::string& source = m.source;
  if (j.contains("name")) {
    if (!j["name"].is_string()) fail(source, "field \"name\" must be a string");
    m.name = j["name"].get<std::string>();
  }
  if (j.contains("time")) {
    if (!j["time"].is_string()) fail(source, "field \"time\" must be a column name");
    m.time_column = j["time"].get<std::string>();
  }
  if (j.contains("sample_time")) {
    m.sample_time = number(j["sample_time"], source, "sample_time");
    if (!(*m.sample_time > 0)) fail(source, "field \"sample_time\" must be positive");
  }
  if (m.time_column.empty() && !m.sample_time)
    fail(source, "give either \"time\" (a column) or \"sample_time\" (in s)");
}

// How each input behaves between samples (sets/data/intersample.hpp reads the values).
void read_intersample(const ojson& j, ModelFile& m) {
  m.intersample = read_texts(j, "intersample", m.source, false);
  for (const auto& [input, mode] : m.intersample) {
    bool is_input = false;
    for (const auto& in : m.inputs) is_input = is_input || in.first == input;
    if (!is_input) fail(m.source, "\"intersample." + input + "\" is not an input");
    if (mode != "zoh" && mode != "foh" && mode != "bl")
      fail(m.source, "field \"intersample." + input + "\" must be \"zoh\" (held), \"foh\" (linear) or \"bl\" (band-limited)");
  }
}

// One entry of "parameters": a number, or {"value", "fixed", "min", "max"}.
ModelParameter read_parameter(const std::string& name, const ojson& v, const std::string& source) {
  ModelParameter p;
  p.name = name;
  const std::string f = "parameters." + printable(p.name, 100);
  if (v.is_number()) {
    p.value = v.get<double>();
    return p;
  }
  if (!v.is_object()) fail(source, "field \"" + f + "\" must be a number or {\"value\": ...}");
  for (auto k = v.begin(); k != v.end(); ++k)
    if (k.key() != "value" && k.key() != "fixed" && k.key() != "min" && k.key() != "max")
      fail(source, "unknown field \"" + f + "." + printable(k.key(), 100) + "\"");
  if (!v.contains("value")) fail(source, "missing field \"" + f + ".value\"");
  p.value = number(v["value"], source, f + ".value");
  if (v.contains("fixed")) {
    if (!v["fixed"].is_boolean()) fail(source, "field \"" + f + ".fixed\" must be true or false");
    p.fixed = v["fixed"].get<bool>();
  }
  if (v.contains("min")) p.min = number(v["min"], source, f + ".min");
  if (v.contains("max")) p.max = number(v["max"], source, f + ".max");
  if (p.min > p.max) fail(source, "field \"" + f + "\": min > max");
  return p;
}

void read_parameters(const ojson& j, ModelFile& m) {
  if (!j.contains("parameters")) return;
  const auto& ps = j["parameters"];
  if (!ps.is_object()) fail(m.source, "field \"parameters\" must be an object");
  for (auto it = ps.begin(); it != ps.end(); ++it) m.parameters.push_back(read_parameter(it.key(), it.value(), m.source));
}

// "states": each with a number or a column giving its initial value.
void read_states(const ojson& j, ModelFile& m) {
  const std::string& source = m.source;
  if (!j.contains("states")) fail(source, "missing field \"states\"");
  if (!j["states"].is_object()) fail(source, "field \"states\" must be an object");
  for (auto it = j["states"].begin(); it != j["states"].end(); ++it) {
    ModelState s;
    s.name = it.key();
    if (it.value().is_number())
      s.initial_value = it.value().get<double>();
    else if (it.value().is_string())
      s.initial_column = it.value().get<std::string>();
    else
      fail(source, "field \"states." + printable(s.name, 100) + "\" must be a number or a column name");
    m.states.push_back(s);
  }
}

// One derivative per state and no other; one name, one meaning; outputs of known symbols.
void check_structure(const ModelFile& m) {
  const std::string& source = m.source;
  if (m.outputs.empty()) fail(source, "field \"outputs\" is empty");
  for (const auto& s : m.states)
    if (!m.derivative(s.name)) fail(source, "state \"" + printable(s.name, 100) + "\" has no entry in \"derivatives\"");
  for (const auto& d : m.derivatives) {
    bool found = false;
    for (const auto& s : m.states) found = found || s.name == d.first;
    if (!found) fail(source, "\"derivatives." + printable(d.first, 100) + "\" is not a state");
  }
  std::vector<std::string> names = {"t", "Ts"};
  auto add = [&](const std::string& n, const char* where) {
    if (const std::string problem = symbol_name_problem(n); !problem.empty())
      fail(source, std::string("field \"") + where + "\": " + problem);
    for (const auto& x : names)
      if (x == n) fail(source, "symbol \"" + n + "\" in \"" + where + "\" is defined twice");
    names.push_back(n);
  };
  for (const auto& e : m.inputs) add(e.first, "inputs");
  for (const auto& p : m.parameters) add(p.name, "parameters");
  for (const auto& s : m.states) add(s.name, "states");
  for (const auto& e : m.signals) add(e.first, "signals");
  for (const auto& e : m.sampled) add(e.first, "sampled");
  for (const auto& o : m.outputs)
    if (!m.has_symbol(o.first)) fail(source, "unknown symbol \"" + printable(o.first, 100) + "\" in \"outputs\"");
}

}  // namespace

ModelFile parse_model(const std::string& text, const std::string& source) {
  // Malformed JSON, 1e400 and absurd nesting: InputError with line and column.
  ojson j = parse_ordered_json_text(text, source);
  if (!j.is_object()) fail(source, "the model must be a JSON object");
  ModelFile m;
  m.source = source;
  check_known_fields(j, source);
  read_name_and_time(j, m);
  m.inputs = read_texts(j, "inputs", source, false);
  read_intersample(j, m);
  read_parameters(j, m);
  read_states(j, m);
  m.signals = read_texts(j, "signals", source, false);
  m.sampled = read_texts(j, "sampled", source, false);
  m.derivatives = read_texts(j, "derivatives", source, true);
  m.outputs = read_texts(j, "outputs", source, true);
  check_structure(m);
  read_units(j, m);
  return m;
}

ModelFile load_model_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the model file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_model(ss.str(), path);
}

std::string to_json_text(const ModelFile& m) {
  ojson j;
  j["name"] = m.name;
  if (!m.time_column.empty()) j["time"] = m.time_column;
  if (m.sample_time) j["sample_time"] = *m.sample_time;
  auto texts = [](const NamedTexts& t) {
    ojson o = ojson::object();
    for (const auto& [k, v] : t) o[k] = v;
    return o;
  };
  if (!m.inputs.empty()) j["inputs"] = texts(m.inputs);
  if (!m.intersample.empty()) j["intersample"] = texts(m.intersample);
  ojson ps = ojson::object();
  for (const auto& p : m.parameters) {
    if (!p.fixed && p.min <= -1e300 && p.max >= 1e300) {
      ps[p.name] = p.value;
      continue;
    }
    ojson o;
    o["value"] = p.value;
    if (p.fixed) o["fixed"] = true;
    if (p.min > -1e300) o["min"] = p.min;
    if (p.max < 1e300) o["max"] = p.max;
    ps[p.name] = o;
  }
  j["parameters"] = ps;
  ojson st = ojson::object();
  for (const auto& s : m.states) {
    if (s.initial_value)
      st[s.name] = *s.initial_value;
    else
      st[s.name] = s.initial_column;
  }
  j["states"] = st;
  if (!m.signals.empty()) j["signals"] = texts(m.signals);
  if (!m.sampled.empty()) j["sampled"] = texts(m.sampled);
  j["derivatives"] = texts(m.derivatives);
  j["outputs"] = texts(m.outputs);
  if (!m.units.empty()) j["units"] = texts(m.units);
  return j.dump(2) + "\n";
}


void save_model_file(const ModelFile& model, const std::string& path) {
  write_file_atomically(path, to_json_text(model));
}

}  // namespace sets
