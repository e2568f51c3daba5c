#include "common/json_output.hpp"

#include "sets/core/atomic_file.hpp"

namespace sets::app {

void write_json(const std::string& path, const Json& j, int indent) {
  if (!path.empty()) write_file_atomically(path, j.dump(indent) + "\n");
}

}  // namespace sets::app
