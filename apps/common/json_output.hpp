#pragma once
// The one way the apps write JSON: nlohmann::json values (keys sorted, as every app has always
// written them), Eigen vectors as arrays, written completely or not at all.

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace sets::app {

using Json = nlohmann::json;

inline Json to_json(const Eigen::Ref<const Eigen::VectorXd>& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}

/// Writes `j` (indented by `indent`, with a final newline) to `path` atomically; nothing if the
/// path is empty. The path was checked before the work (Cli::add_output_file).
void write_json(const std::string& path, const Json& j, int indent = 2);

}  // namespace sets::app
