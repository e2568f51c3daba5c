#include "structure_flags.hpp"

#include <fstream>
#include <sstream>

#include "sets/core/error.hpp"
#include "sets/examples/cerone_regruto.hpp"

using sets::LpvModelStructure;

LpvModelStructure structure_from_flags(const std::string& model_file, const std::vector<std::string>& a_flags,
                                       const std::vector<std::string>& b_flags, int alpha) {
  if (!model_file.empty()) {
    if (!a_flags.empty() || !b_flags.empty())
      throw sets::InputError("give the model structure either by --model or by --a/--b, not both");
    std::ifstream in(model_file);
    if (!in) throw sets::InputError("cannot open model file '" + model_file + "'");
    std::stringstream ss;
    ss << in.rdbuf();
    LpvModelStructure m = sets::parse_lpv_structure_json(ss.str(), model_file);
    if (m.alpha != alpha)
      throw sets::InputError(model_file + ": alpha = " + std::to_string(m.alpha) + " but " + std::to_string(alpha) +
                             " scheduling columns were given with --r");
    return m;
  }
  if (a_flags.empty() && b_flags.empty()) {
    if (alpha != 1) throw sets::InputError("with several --r columns give the model structure (--model or --a/--b)");
    return sets::cerone_regruto::structure();
  }
  if (b_flags.empty()) throw sets::InputError("--b is required with --a (one --b per b_j, j = 0..nb; \"\" for none)");
  LpvModelStructure m;
  m.alpha = alpha;
  auto parse_list = [&](const std::string& text, const std::string& flag) {
    std::vector<sets::BasisFunction> basis;
    std::stringstream ss(text);
    std::string item;
    while (std::getline(ss, item, ',')) {
      if (item.find_first_not_of(" \t") == std::string::npos) continue;
      try {
        basis.push_back(sets::parse_basis_function(item, alpha));
      } catch (const sets::InputError& e) {
        throw sets::InputError(flag + " '" + text + "': " + e.what());
      }
    }
    return basis;
  };
  for (std::size_t i = 0; i < a_flags.size(); ++i) m.a.push_back(parse_list(a_flags[i], "--a #" + std::to_string(i + 1)));
  for (std::size_t j = 0; j < b_flags.size(); ++j) m.b.push_back(parse_list(b_flags[j], "--b #" + std::to_string(j + 1)));
  m.validate();
  return m;
}

