#pragma once
// A recording: named columns of equal length (CSV with a header line, or a MATLAB .mat file read
// with matio, where each vector variable is a column).

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
};

/// CSV: header line of names, then numbers. Errors name file, line and column; a NaN or Inf names
/// its row (data row numbering starts at 1, the header is line 1).
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
