#pragma once
// GLPK calls abort() on an internal error (a violated precondition, exhausted memory, a bug)
// unless an error hook is installed. Every GLPK call of the library runs through call_glpk:
// the hook jumps back (longjmp, the way out GLPK's manual documents), the thread's GLPK
// environment, now inconsistent, is freed, and a NumericalError carrying GLPK's message is
// thrown on the calling thread. No abort() is reachable through the library.
//
// Freeing the environment frees every GLPK problem of the thread: a LinearProgram notices
// (glpk_environment_generation() changed) and rebuilds its problem from its own copy of the
// data on next use, cold (its basis is lost).

#include <type_traits>

namespace sets {

/// Runs fn(data) with GLPK's error hook installed. fn is C-style on purpose: the jump skips
/// every frame between GLPK's error and this call, so nothing there may own resources (do the
/// allocations before, call only glp_* inside). Throws NumericalError("<what>: GLPK internal
/// error: <GLPK's message>") after an internal error; exceptions thrown by fn itself propagate.
void call_glpk(const char* what, void (*fn)(void*), void* data);

/// Runs f() (a callable that calls only GLPK) through call_glpk.
template <class F>
void call_glpk(const char* what, F&& f) {
  call_glpk(what, [](void* d) { (*static_cast<std::remove_reference_t<F>*>(d))(); }, &f);
}

/// How many times this thread's GLPK environment was freed (after an internal error, or by
/// note_glpk_environment_freed's callers). GLPK problems created before a change are gone.
unsigned long glpk_environment_generation();
/// To be called right after glp_free_env() by any code that frees the thread's environment.
void note_glpk_environment_freed();

}  // namespace sets
