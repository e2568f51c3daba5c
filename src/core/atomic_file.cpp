#include "sets/core/atomic_file.hpp"

#include <filesystem>
#include <fstream>

#include "sets/core/error.hpp"

namespace sets {

void write_file_atomically(const std::string& path, const std::string& text) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  std::string tmp_name = target.filename().string();
  tmp_name.insert(tmp_name.begin(), '.');  // hidden temporary beside the target
  tmp_name += ".tmp";
  const fs::path tmp = target.parent_path() / tmp_name;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot write (folder missing or not writable)");
    out << text;
    out.flush();
    if (!out) {
      out.close();
      std::error_code ec;
      fs::remove(tmp, ec);
      throw InputError(path + ": write failed");
    }
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw InputError(path + ": cannot rename the finished file into place");
  }
}

}  // namespace sets
