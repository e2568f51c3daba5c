#pragma once
// A recording: named columns of equal length (CSV with a header line, or a MATLAB .mat file read
// with matio, where each vector variable is a column).

#include <Eigen/Core>

#include <string>
#include <vector>

namespace sets {

struct Recording {
  std::string source;                     // file name for messages
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;

  int rows() const { return columns.empty() ? 0 : static_cast<int>(columns.front().size()); }
  bool has(const std::string& name) const;
  /// The column, or InputError naming the missing column and the file.
  const std::vector<double>& column(const std::string& name) const;
  void add(const std::string& name, std::vector<double> values);

  /// The column called `name_or_number`, or if none is, the column of that number (from 1).
  /// InputError naming `what` (e.g. the flag that gave it), the file and its columns.
  std::size_t column_index(const std::string& name_or_number, const std::string& what = {}) const;
  /// Those columns side by side: samples x columns.
  Eigen::MatrixXd matrix(const std::vector<std::string>& names_or_numbers, const std::string& what = {}) const;
};

/// CSV: header line of names, then numbers. Errors name file, line and column; a NaN or Inf names
/// its row (data row numbering starts at 1, the header is line 1).
/// A first line of numbers only is data, not a header: the columns are then named "1", "2", ...
/// Fields are separated by commas or, when the first line has none, by semicolons or tabs; blank
/// lines and lines starting with '#' are skipped; a number may start with '+'.
Recording read_csv(const std::string& path);
Recording parse_csv(const std::string& text, const std::string& source);
/// MATLAB .mat (v4/v5/v7.3 as matio reads them): every real numeric vector of the most common
/// length becomes a column (scalars such as gains are skipped).
Recording read_mat(const std::string& path);
/// By extension: .mat -> read_mat, anything else -> read_csv.
Recording read_recording(const std::string& path);
/// Writes a CSV (complete or not at all).
void write_csv(const Recording& r, const std::string& path);

}  // namespace sets
