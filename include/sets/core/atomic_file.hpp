#pragma once
// Output files are written completely or not at all.

#include <string>

namespace sets {

/// Writes `text` to `path` through a hidden temporary file in the same folder and renames it into
/// place, so a reader never sees a half-written file. Throws InputError naming the path.
void write_file_atomically(const std::string& path, const std::string& text);

}  // namespace sets
