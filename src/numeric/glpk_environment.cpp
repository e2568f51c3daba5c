#include "sets/numeric/glpk_environment.hpp"

#include <glpk.h>

namespace sets {

// glp_free_env returns 1 when the thread has no environment (nothing was solved on it): nothing
// to do then, and no environment is created just to free it.
GlpkThreadEnvironment::~GlpkThreadEnvironment() { glp_free_env(); }

}  // namespace sets
