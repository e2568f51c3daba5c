#pragma once
// Reading the numeric vectors of a MATLAB .mat file from its bytes, hardened against hostile
// files: every size is checked against the bytes that are really there before anything is
// allocated, compressed variables are inflated under a cap, and nothing outside the buffer is read.
//
// Level 4 and level 5 (v5, v6, v7: the default of MATLAB's `save`) files are read here. matio
// (Debian 1.5.23) crashes, hangs or allocates gigabytes on fuzzed level 5 files, and checking a
// file well enough to hand it to matio safely is as much code as reading the vectors ourselves.
// v7.3 files are HDF5 and are left to matio (see read_mat).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace sets {

/// Limits of the .mat reader (bytes of one variable once inflated; elements of one vector).
inline constexpr std::size_t max_mat_variable_bytes = std::size_t{1} << 30;
inline constexpr std::size_t max_mat_elements = std::size_t{1} << 27;

enum class Mat_format { v4, v5, v73, unknown };

/// Which format the bytes are (v7.3: the v5 header with version 0x0200).
Mat_format mat_format(std::string_view bytes);

struct Mat_vector {
  std::string name;
  std::vector<double> values;
};

/// Every real numeric variable that is a vector with more than one element, in file order; other
/// variables (scalars, matrices, complex, char, cell, struct, sparse, objects) are skipped.
/// Throws InputError naming `path` and the byte offset of a malformed element.
std::vector<Mat_vector> read_mat_v4_vectors(std::string_view bytes, const std::string& path);
std::vector<Mat_vector> read_mat_v5_vectors(std::string_view bytes, const std::string& path);

}  // namespace sets
