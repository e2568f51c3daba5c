#include "sets/numeric/glpk_environment.hpp"

#include <glpk.h>

#include "sets/numeric/glpk_error.hpp"

namespace sets {

// glp_free_env returns 1 when the thread has no environment (nothing was solved on it): nothing
// to do then, and no environment is created just to free it.
GlpkThreadEnvironment::~GlpkThreadEnvironment() {
  if (glp_free_env() == 0) note_glpk_environment_freed();  // LinearPrograms left over must not free theirs
}

}  // namespace sets
