// libFuzzer harness: the set text reader (from_string, which load_text uses). A set that reads
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
        const sets::AnySet s = sets::from_string(text, "fuzz.txt");
        const std::string again = sets::to_string(s);
        try {
          (void)sets::from_string(again, "written.txt");
        } catch (const sets::InputError& e) {
          sets::fuzz::bug(std::string("the written set does not read back: ") + e.what() + "\n" + again);
        }
      },
      "fuzz.txt");
  return 0;
}
