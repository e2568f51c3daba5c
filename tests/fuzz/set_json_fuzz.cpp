// libFuzzer harness: the set JSON reader (parse_set_json, which load_json uses). A set that reads
// must write and read back.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"
#include "sets/domains/set_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  sets::fuzz::expect_documented_errors(
      [&] {
        const sets::AnySet s = sets::parse_set_json(text, "fuzz.json");
        const std::string again = sets::to_json(s).dump();
        try {
          (void)sets::parse_set_json(again, "written.json");
        } catch (const sets::InputError& e) {
          sets::fuzz::bug(std::string("the written set does not read back: ") + e.what() + "\n" + again);
        }
      },
      "fuzz.json");
  return 0;
}
