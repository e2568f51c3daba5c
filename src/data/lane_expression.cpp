#include "data/lane_expression.hpp"

#include <muParserTemplateMagic.h>

#include <algorithm>
#include <string>
#include <type_traits>

#include "sets/core/error.hpp"

namespace sets {

Lane_expression::Lane_expression(const mu::ParserBase& parser, const std::function<int(const double*)>& slot_of) {
  int depth = 0, deepest = 0;
  for (const mu::SToken* t = parser.GetByteCode().GetBase(); t->Cmd != mu::cmEND; ++t) {
    Op op{t->Cmd};
    switch (t->Cmd) {
      case mu::cmVAR: op.slot = slot_of(t->Val.ptr); ++depth; break;
      case mu::cmVAL: op.value = t->Val.data2; ++depth; break;
      case mu::cmFUNC:
        op.argc = t->Fun.argc;
        op.fun = t->Fun.cb;
        depth += op.argc == 0 ? 1 : op.argc > 0 ? 1 - op.argc : 1 + op.argc;  // negative: -argc arguments
        break;
      case mu::cmIF: op.offset = t->Oprt.offset; --depth; break;
      case mu::cmELSE: op.offset = t->Oprt.offset; break;
      case mu::cmENDIF: break;
      case mu::cmLE: case mu::cmGE: case mu::cmNEQ: case mu::cmEQ: case mu::cmLT: case mu::cmGT:
      case mu::cmADD: case mu::cmSUB: case mu::cmMUL: case mu::cmDIV: case mu::cmPOW:
      case mu::cmLAND: case mu::cmLOR:
        --depth;
        break;
      default:  // what compile_expression never produces (the optimiser's tokens, strings, assignment)
        throw NumericalError("Lane_expression: bytecode token " + std::to_string(static_cast<int>(t->Cmd)) +
                             " is not evaluated lane by lane");
    }
    // Counting both branches of c ? a : b one after the other overstates the depth: safe.
    deepest = std::max(deepest, depth);
    ops_.push_back(op);
  }
  stack_size_ = static_cast<std::size_t>(deepest) + 2;  // muparser's stack starts at index 1
}

void Lane_expression::eval(const double* values, int lanes, double* out) const {
  if (stack_.size() < stack_size_ * static_cast<std::size_t>(lanes)) stack_.resize(stack_size_ * static_cast<std::size_t>(lanes));
  const auto together = [&]() -> bool {
    switch (lanes) {
      case 2: return eval_together(values, std::integral_constant<std::size_t, 2>{}, out);
      case 3: return eval_together(values, std::integral_constant<std::size_t, 3>{}, out);
      case 4: return eval_together(values, std::integral_constant<std::size_t, 4>{}, out);
      case 5: return eval_together(values, std::integral_constant<std::size_t, 5>{}, out);
      case 6: return eval_together(values, std::integral_constant<std::size_t, 6>{}, out);
      case 7: return eval_together(values, std::integral_constant<std::size_t, 7>{}, out);
      case 8: return eval_together(values, std::integral_constant<std::size_t, 8>{}, out);
      default: return eval_together(values, static_cast<std::size_t>(lanes), out);
    }
  };
  if (together()) return;
  for (int l = 0; l < lanes; ++l) out[l] = eval_lane(values, lanes, l);
}

// All lanes at once, each operation as ParseCmdCodeBulk does it. False where the lanes part at a
// condition.
template <class Lanes>
bool Lane_expression::eval_together(const double* values, Lanes L, double* out) const {
  double* s = stack_.data();
  std::size_t top = 0;  // index of the top entry (muparser's sidx)
  const Op* const end = ops_.data() + ops_.size();
  for (const Op* op = ops_.data(); op != end; ++op) {
    // The top (b) and the entry below it (a: a binary operation's left side and result); the
    // stack's index 0 is never used, so top - 1 exists whenever an operation reads it.
    double* b = s + top * L;
    double* a = top > 0 ? b - L : b;
    switch (op->cmd) {
      case mu::cmLE: for (std::size_t l = 0; l < L; ++l) a[l] = a[l] <= b[l]; --top; continue;
      case mu::cmGE: for (std::size_t l = 0; l < L; ++l) a[l] = a[l] >= b[l]; --top; continue;
      case mu::cmNEQ: for (std::size_t l = 0; l < L; ++l) a[l] = a[l] != b[l]; --top; continue;
      case mu::cmEQ: for (std::size_t l = 0; l < L; ++l) a[l] = a[l] == b[l]; --top; continue;
      case mu::cmLT: for (std::size_t l = 0; l < L; ++l) a[l] = a[l] < b[l]; --top; continue;
      case mu::cmGT: for (std::size_t l = 0; l < L; ++l) a[l] = a[l] > b[l]; --top; continue;
      case mu::cmADD: for (std::size_t l = 0; l < L; ++l) a[l] += b[l]; --top; continue;
      case mu::cmSUB: for (std::size_t l = 0; l < L; ++l) a[l] -= b[l]; --top; continue;
      case mu::cmMUL: for (std::size_t l = 0; l < L; ++l) a[l] *= b[l]; --top; continue;
      case mu::cmDIV: for (std::size_t l = 0; l < L; ++l) a[l] /= b[l]; --top; continue;
      case mu::cmPOW: for (std::size_t l = 0; l < L; ++l) a[l] = mu::MathImpl<double>::Pow(a[l], b[l]); --top; continue;
      case mu::cmLAND: for (std::size_t l = 0; l < L; ++l) a[l] = a[l] && b[l]; --top; continue;
      case mu::cmLOR: for (std::size_t l = 0; l < L; ++l) a[l] = a[l] || b[l]; --top; continue;
      case mu::cmVAR: {
        const double* v = values + static_cast<std::size_t>(op->slot) * L;
        double* c = b + L;
        for (std::size_t l = 0; l < L; ++l) c[l] = v[l];
        ++top;
        continue;
      }
      case mu::cmVAL: {
        double* c = b + L;
        for (std::size_t l = 0; l < L; ++l) c[l] = op->value;
        ++top;
        continue;
      }
      case mu::cmIF: {
        const bool taken = b[0] == 0;
        for (std::size_t l = 1; l < L; ++l)
          if ((b[l] == 0) != taken) return false;
        --top;
        if (taken) op += op->offset;
        continue;
      }
      case mu::cmELSE: op += op->offset; continue;
      case mu::cmENDIF: continue;
      case mu::cmFUNC: {
        const int argc = op->argc;
        if (argc == 1) {
          for (std::size_t l = 0; l < L; ++l) b[l] = op->fun.call_fun<1>(b[l]);
        } else if (argc == 2) {
          for (std::size_t l = 0; l < L; ++l) a[l] = op->fun.call_fun<2>(a[l], b[l]);
          --top;
        } else {
          // Rare shapes (no argument, three or more, any number): lane by lane through the same stack.
          const std::size_t n = static_cast<std::size_t>(argc == 0 ? 0 : argc > 0 ? argc : -argc);
          const std::size_t first = top + 1 - n;  // index of the first argument (top + 1 when none)
          double args[32];
          if (n > 32) return false;
          for (std::size_t l = 0; l < L; ++l) {
            for (std::size_t i = 0; i < n; ++i) args[i] = s[(first + i) * L + l];
            double r;
            switch (argc) {
              case 0: r = op->fun.call_fun<0>(); break;
              case 3: r = op->fun.call_fun<3>(args[0], args[1], args[2]); break;
              default:
                if (argc > 0) return false;
                r = op->fun.call_multfun(args, -argc);
            }
            s[first * L + l] = r;
          }
          top = first;
        }
        continue;
      }
      default: return false;
    }
  }
  const double* r = s + L;  // a single result sits at index 1, as muparser's m_nFinalResultIdx
  for (std::size_t l = 0; l < L; ++l) out[l] = r[l];
  return true;
}

// One lane, the same operations: where the lanes part at a condition.
double Lane_expression::eval_lane(const double* values, int lanes, int lane) const {
  const auto L = static_cast<std::size_t>(lanes);
  const auto at = static_cast<std::size_t>(lane);
  double* s = stack_.data();
  std::size_t top = 0;
  const Op* const end = ops_.data() + ops_.size();
  for (const Op* op = ops_.data(); op != end; ++op) {
    double& b = s[top];
    double& a = s[top > 0 ? top - 1 : 0];
    switch (op->cmd) {
      case mu::cmLE: a = a <= b; --top; continue;
      case mu::cmGE: a = a >= b; --top; continue;
      case mu::cmNEQ: a = a != b; --top; continue;
      case mu::cmEQ: a = a == b; --top; continue;
      case mu::cmLT: a = a < b; --top; continue;
      case mu::cmGT: a = a > b; --top; continue;
      case mu::cmADD: a += b; --top; continue;
      case mu::cmSUB: a -= b; --top; continue;
      case mu::cmMUL: a *= b; --top; continue;
      case mu::cmDIV: a /= b; --top; continue;
      case mu::cmPOW: a = mu::MathImpl<double>::Pow(a, b); --top; continue;
      case mu::cmLAND: a = a && b; --top; continue;
      case mu::cmLOR: a = a || b; --top; continue;
      case mu::cmVAR: s[++top] = values[static_cast<std::size_t>(op->slot) * L + at]; continue;
      case mu::cmVAL: s[++top] = op->value; continue;
      case mu::cmIF:
        if (s[top--] == 0) op += op->offset;
        continue;
      case mu::cmELSE: op += op->offset; continue;
      case mu::cmENDIF: continue;
      case mu::cmFUNC: {
        const int argc = op->argc;
        switch (argc) {
          case 0: s[++top] = op->fun.call_fun<0>(); continue;
          case 1: b = op->fun.call_fun<1>(b); continue;
          case 2: a = op->fun.call_fun<2>(a, b); --top; continue;
          case 3: top -= 2; s[top] = op->fun.call_fun<3>(s[top], s[top + 1], s[top + 2]); continue;
          default:
            if (argc > 0) throw NumericalError("Lane_expression: a function of " + std::to_string(argc) + " arguments");
            top -= static_cast<std::size_t>(-argc - 1);
            s[top] = op->fun.call_multfun(&s[top], -argc);
            continue;
        }
      }
      default: throw NumericalError("Lane_expression: unexpected bytecode token");
    }
  }
  return s[1];
}

}  // namespace sets
