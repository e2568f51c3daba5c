// libFuzzer harness: the CSV recording reader (parse_csv).
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"
#include "sets/data/recording.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  sets::fuzz::expect_documented_errors(
      [&] {
        const sets::Recording r = sets::parse_csv(text, "fuzz.csv");
        for (const auto& c : r.columns)
          if (static_cast<int>(c.size()) != r.rows()) sets::fuzz::bug("columns of different lengths");
        // A missing column is named in its message, escaped.
        const std::string missing = "\x1b[31mnot there";
        if (!r.has(missing)) {
          try {
            (void)r.column(missing);
            sets::fuzz::bug("column() found a column that is not there");
          } catch (const sets::InputError& e) {
            sets::fuzz::check_message(e, "fuzz.csv");
          }
        }
      },
      "fuzz.csv");
  return 0;
}
