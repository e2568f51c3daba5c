// libFuzzer harness: the JSON model file reader (parse_model). A model that parses must also
// survive a round trip through to_json_text.
#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.hpp"
#include "sets/models/model_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  sets::fuzz::expect_documented_errors(
      [&] {
        const sets::ModelFile m = sets::parse_model(text, "fuzz.json");
        const std::string again = sets::to_json_text(m);
        try {
          if (sets::to_json_text(sets::parse_model(again, "written.json")) != again)
            sets::fuzz::bug("the written model does not read back the same:\n" + again);
        } catch (const sets::InputError& e) {
          sets::fuzz::bug(std::string("the written model does not read back: ") + e.what() + "\n" + again);
        }
      },
      "fuzz.json");
  return 0;
}
