#pragma once
// One expression evaluated for several lanes at once: the lanes are simulations of the same model
// with different parameter values (a finite-difference Jacobian's columns). muparser interprets its
// bytecode one value at a time, and its dispatch per token is most of a simulation's cost; here the
// dispatch is paid once per token for all lanes.
//
// Each lane's value is bit for bit muparser's: the same bytecode (optimiser off, as
// compile_expression sets it), the same operations in the same order as
// ParserBase::ParseCmdCodeBulk of muparser 2.3.3, the same function pointers. Where the lanes take
// different branches of `c ? a : b`, the expression is evaluated lane by lane.

#include <muParser.h>

#include <functional>
#include <vector>

namespace sets {

class Lane_expression {
 public:
  /// Reads the bytecode of `parser` (evaluated once already, so that it exists). `slot_of`
  /// gives the slot number of each variable address the bytecode holds.
  Lane_expression(const mu::ParserBase& parser, const std::function<int(const double*)>& slot_of);

  /// out[l] = the expression with every variable read from values[slot * lanes + l], l < lanes.
  void eval(const double* values, int lanes, double* out) const;

 private:
  struct Op {
    mu::ECmdCode cmd;
    int slot = -1;       // cmVAR
    double value = 0;    // cmVAL
    int argc = 0;        // cmFUNC (negative: a function of any number of arguments)
    int offset = 0;      // cmIF, cmELSE: tokens to skip
    mu::generic_callable_type fun{};
  };
  // Lanes: a std::size_t, or a std::integral_constant for the common counts (loops the compiler
  // unrolls and vectorises).
  template <class Lanes>
  bool eval_together(const double* values, Lanes lanes, double* out) const;
  double eval_lane(const double* values, int lanes, int lane) const;

  std::vector<Op> ops_;
  std::size_t stack_size_ = 0;
  mutable std::vector<double> stack_;  // scratch: one Lane_expression per thread, as muparser's parser
};

}  // namespace sets
