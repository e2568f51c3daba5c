// Computes the PUIs of a tiny bounded-error problem through the installed library.
#include <sets/sets.hpp>  // the umbrella header: every public header

#include <iostream>

int main() {
  Eigen::MatrixXd Phi(3, 1);
  Phi << 1, 2, 3;
  Eigen::VectorXd y(3), delta = Eigen::VectorXd::Constant(3, 0.1);
  y << 1.0, 2.1, 2.9;
  const auto r = sets::pui(sets::FeasibleParameterSet::from_data(Phi, y, delta));
  std::cout << "consumer: theta in " << sets::to_string(r.box[0]) << (r.guaranteed ? " (guaranteed)" : "") << '\n';
  return r.guaranteed && r.box[0].lower() <= 1.0 && 1.0 <= r.box[0].upper() ? 0 : 1;
}
