#pragma once
// Reading numeric columns of a CSV file for sets-ss-uncertainty (errors name file, line, column).

#include <Eigen/Core>

#include <string>
#include <vector>

struct CsvTable {
  std::vector<std::string> header;  // empty when the file has none
  Eigen::MatrixXd data;             // rows = samples
};

/// Comma, semicolon or tab separated; a first line that is not all numbers is the header;
/// lines starting with '#' and empty lines are skipped. Throws sets::InputError.
CsvTable read_csv(const std::string& path);

/// "1,3" (1-based) or "u1,u2" (header names) -> 0-based column indices. Throws sets::InputError.
std::vector<int> parse_columns(const std::string& spec, const CsvTable& table, const std::string& flag);
