#pragma once
// Umbrella header: every public header of `sets`, layer by layer (docs/architecture.md).
// Include the per-concept headers instead to keep build times short.

#include "sets/core/atomic_file.hpp"
#include "sets/core/bool_interval.hpp"
#include "sets/core/error.hpp"
#include "sets/core/exit_code.hpp"
#include "sets/core/printable.hpp"

#include "sets/numeric/interval.hpp"
#include "sets/numeric/interval_matrix.hpp"
#include "sets/numeric/linear_program.hpp"
#include "sets/numeric/safe_bound.hpp"
#include "sets/numeric/tight_range.hpp"

#include "sets/domains/conversions.hpp"
#include "sets/domains/ellipsoid.hpp"
#include "sets/domains/hpolytope.hpp"
#include "sets/domains/set_io.hpp"
#include "sets/domains/set_operations.hpp"
#include "sets/domains/vpolytope.hpp"
#include "sets/domains/zonotope.hpp"

#include "sets/fps/feasible_parameter_set.hpp"
#include "sets/fps/outer_zonotope.hpp"

#include "sets/models/lpv_model.hpp"
#include "sets/models/model_file.hpp"
#include "sets/models/orthonormal_basis.hpp"
#include "sets/models/state_space_model.hpp"
#include "sets/models/transfer_function.hpp"
#include "sets/models/time_varying_model.hpp"

#include "sets/data/intersample.hpp"
#include "sets/data/noise_level.hpp"
#include "sets/data/recording.hpp"
#include "sets/data/simulation.hpp"
#include "sets/data/spectrum.hpp"

#include "sets/methods/lpv_pui/lpv_pui.hpp"

#include "sets/methods/ss_uncertainty/level_set_uncertainty.hpp"
#include "sets/methods/ss_uncertainty/propagator_identification.hpp"
#include "sets/methods/ss_uncertainty/ss_uncertainty.hpp"
#include "sets/methods/ss_uncertainty/canonical_fps.hpp"
#include "sets/methods/ss_uncertainty/state_enclosure.hpp"

#include "sets/methods/hinf_bound/hinf_bound.hpp"

#include "sets/methods/tv_bound/tv_bound.hpp"
#include "sets/methods/tv_bound/tv_relinearisation.hpp"
#include "sets/methods/tv_bound/window_norm.hpp"

#include "sets/diagnosis/calibration.hpp"
#include "sets/diagnosis/diagnosis.hpp"
#include "sets/diagnosis/equation_error.hpp"
#include "sets/diagnosis/physics_catalogue.hpp"

#include "sets/examples/crane.hpp"
#include "sets/examples/farah.hpp"
#include "sets/examples/farah_study.hpp"
#include "sets/examples/synthetic_plants.hpp"
