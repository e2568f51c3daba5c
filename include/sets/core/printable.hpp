#pragma once
// Text from an input file quoted in a message: a terminal must never receive its raw bytes.

#include <cstddef>
#include <string>
#include <string_view>

namespace sets {

/// `text` safe to print: control characters (C0, DEL and C1), and bytes that are not part of valid
/// UTF-8, become \xNN (\n, \r, \t as such); printable UTF-8 is kept. Longer than
/// `max_bytes` of input, the rest is replaced by "...".
std::string printable(std::string_view text, std::size_t max_bytes = 200);

}  // namespace sets
