// libFuzzer harness: the MATLAB .mat reader (read_mat), which reads from a path: each input is
// written to a file of this process first.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "fuzz_support.hpp"
#include "sets/data/recording.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = [] {
    const char* dir = std::getenv("TMPDIR");
    std::string p = std::string(dir && *dir ? dir : "/tmp") + "/sets-fuzz-mat-" + std::to_string(getpid()) + ".mat";
    std::atexit([] { std::remove(path.c_str()); });
    return p;
  }();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) sets::fuzz::bug("cannot write " + path);
  if (size > 0 && std::fwrite(data, 1, size, f) != size) sets::fuzz::bug("cannot write " + path);
  std::fclose(f);
  sets::fuzz::expect_documented_errors(
      [&] {
        const sets::Recording r = sets::read_mat(path);
        for (const auto& c : r.columns)
          if (static_cast<int>(c.size()) != r.rows()) sets::fuzz::bug("columns of different lengths");
      },
      path);
  return 0;
}
