#include "sets/fps/falsification.hpp"

#include <ostream>
#include <sstream>

namespace sets {

std::string Falsification::message() const {
  std::ostringstream os;
  os << "the data falsify the model: no parameter value satisfies all samples";
  if (!samples.empty()) {
    os << "; these samples conflict (sample: violation of the best compromise):";
    for (std::size_t i = 0; i < samples.size(); ++i) os << ' ' << samples[i] << ": " << violation[i];
  }
  return os.str();
}

std::string ConsistencyVerdict::message() const {
  switch (falsified) {
    case Falsified::yes: return conflict.message() + " (certified in exact arithmetic)";
    case Falsified::no: return "the data are consistent with the model: a parameter value satisfies every sample";
    default: return "whether the data falsify the model could not be decided" + (reason.empty() ? "" : ": " + reason);
  }
}

const char* to_string(Falsified f) {
  switch (f) {
    case Falsified::no: return "no";
    case Falsified::yes: return "yes";
    default: return "unknown";
  }
}

std::ostream& operator<<(std::ostream& os, Falsified f) { return os << to_string(f); }

}  // namespace sets
