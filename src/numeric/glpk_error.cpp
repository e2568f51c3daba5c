#include "sets/numeric/glpk_error.hpp"

#include <glpk.h>

#include <csetjmp>
#include <string>

#include "sets/core/error.hpp"

namespace sets {

namespace {

thread_local unsigned long generation = 0;

struct ErrorContext {
  std::jmp_buf jump;
  std::string message;  // GLPK's terminal output during the call (its error text)
};

extern "C" void on_glpk_error(void* info) { std::longjmp(static_cast<ErrorContext*>(info)->jump, 1); }

extern "C" int on_glpk_output(void* info, const char* s) {
  auto& message = static_cast<ErrorContext*>(info)->message;
  if (message.size() < 4000) message += s;
  return 1;  // never printed: the library writes nothing to the terminal
}

std::string one_line(std::string s) {
  for (char& c : s)
    if (c == '\n' || c == '\r') c = ' ';
  while (!s.empty() && s.back() == ' ') s.pop_back();
  return s.empty() ? "(no message)" : s;
}

}  // namespace

unsigned long glpk_environment_generation() { return generation; }
void note_glpk_environment_freed() { ++generation; }

void call_glpk(const char* what, void (*fn)(void*), void* data) {
  ErrorContext context;
  if (setjmp(context.jump) == 0) {
    glp_error_hook(on_glpk_error, &context);
    glp_term_hook(on_glpk_output, &context);
    const int terminal = glp_term_out(GLP_ON);  // to the hook only: GLPK's message names the error
    const auto uninstall = [&] {
      glp_term_out(terminal);
      glp_term_hook(nullptr, nullptr);
      glp_error_hook(nullptr, nullptr);
    };
    try {
      fn(data);
    } catch (...) {
      uninstall();
      throw;
    }
    uninstall();
    return;
  }
  // GLPK's state is inconsistent after an internal error: free the whole environment (the next
  // GLPK call creates a fresh one) and tell this thread's problems theirs are gone.
  glp_free_env();
  note_glpk_environment_freed();
  throw NumericalError(std::string(what) + ": GLPK internal error: " + one_line(context.message));
}

}  // namespace sets
