#include "sets/hpolytope.hpp"

#include <string>

#include "sets/error.hpp"

namespace sets {

HPolytope::HPolytope(Eigen::MatrixXd A, Eigen::VectorXd b) : A_(std::move(A)), b_(std::move(b)) {
  if (A_.rows() != b_.size())
    throw InputError("HPolytope: A has " + std::to_string(A_.rows()) + " rows but b has " +
                     std::to_string(b_.size()) + " entries");
  if (A_.hasNaN() || b_.hasNaN()) throw InputError("HPolytope: A or b contains NaN");
}

}  // namespace sets
