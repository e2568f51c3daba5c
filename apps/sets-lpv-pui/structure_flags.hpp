#pragma once
// sets-lpv-pui: the model structure from --model FILE.json or from --a/--b basis lists.

#include <string>
#include <vector>

#include "sets/models/lpv_model.hpp"

/// --model, or --a/--b (one comma-separated basis list per coefficient), or by default (one
/// scheduling column) the structure of Cerone & Regruto's example. InputError names the flag.
sets::LpvModelStructure structure_from_flags(const std::string& model_file, const std::vector<std::string>& a_flags,
                                             const std::vector<std::string>& b_flags, int alpha);
