#pragma once
// GLPK keeps one environment per thread (thread-local: its memory pool and every problem object
// created on the thread). The first GLPK call on a thread creates it and GLPK never frees it on its
// own, so a worker thread that ends without glp_free_env leaks it (LeakSanitizer reports it).
// Every thread the library, the apps or the tests start that may solve an LP (through
// LinearProgram or anything built on it) holds a GlpkThreadEnvironment for its whole run.

namespace sets {

/// Frees the calling thread's GLPK environment, if GLPK created one, when it goes out of scope.
/// Declare it first in a worker thread's function: glp_free_env also frees every GLPK problem
/// still alive on the thread, so every LinearProgram of the thread must be gone before it.
/// For threads the caller starts and ends; never in code that may run on a thread which keeps
/// LPs beyond the scope (e.g. the main thread).
class GlpkThreadEnvironment {
 public:
  GlpkThreadEnvironment() = default;
  ~GlpkThreadEnvironment();
  GlpkThreadEnvironment(const GlpkThreadEnvironment&) = delete;
  GlpkThreadEnvironment& operator=(const GlpkThreadEnvironment&) = delete;
};

}  // namespace sets
