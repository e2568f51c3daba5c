#include "sets/data/recording.hpp"

#include <boost/algorithm/string/classification.hpp>
#include <boost/algorithm/string/trim.hpp>
#include <matio.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <cstdlib>
#include <map>
#include <mutex>
#include <set>
#include <sstream>

#include "data/mat_file.hpp"
#include "sets/core/error.hpp"
#include "sets/core/printable.hpp"
#include "sets/models/model_file.hpp"

namespace sets {

bool Recording::has(const std::string& name) const {
  for (const auto& n : names)
    if (n == name) return true;
  return false;
}

const std::vector<double>& Recording::column(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return columns[i];
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + printable(n, 60);
  throw InputError(source + ": missing column \"" + printable(name, 100) + "\" (the file has: " + printable(list, 400) + ")");
}

void Recording::add(const std::string& name, std::vector<double> values) {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) {
      columns[i] = std::move(values);
      return;
    }
  names.push_back(name);
  columns.push_back(std::move(values));
}

std::size_t Recording::column_index(const std::string& name_or_number, const std::string& what) const {
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == name_or_number) return i;
  if (!name_or_number.empty() && name_or_number.find_first_not_of("0123456789") == std::string::npos &&
      name_or_number.size() < 10) {
    const std::size_t k = std::stoul(name_or_number);
    if (k >= 1 && k <= names.size()) return k - 1;
  }
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + printable(n, 60);
  throw InputError(source + ": no column \"" + printable(name_or_number, 100) + "\"" +
                   (what.empty() ? "" : " (given by " + what + ")") + "; the file has: " + printable(list, 400) +
                   " (or give a column number from 1 to " + std::to_string(names.size()) + ")");
}

Eigen::MatrixXd Recording::matrix(const std::vector<std::string>& names_or_numbers, const std::string& what) const {
  Eigen::MatrixXd m(rows(), static_cast<Eigen::Index>(names_or_numbers.size()));
  for (std::size_t k = 0; k < names_or_numbers.size(); ++k) {
    const auto& c = columns[column_index(names_or_numbers[k], what)];
    m.col(static_cast<Eigen::Index>(k)) = Eigen::Map<const Eigen::VectorXd>(c.data(), static_cast<Eigen::Index>(c.size()));
  }
  return m;
}

namespace {

// A CSV field without surrounding blanks, carriage returns or quotes.
std::string trim(const std::string& s) { return boost::algorithm::trim_copy_if(s, boost::is_any_of(" \t\r\"")); }

}  // namespace

namespace {

bool skipped(const std::string& line) {
  const std::string t = trim(line);
  return t.empty() || t[0] == '#';
}

enum class Parsed { number, too_large, not_a_number };

// The whole of `cell` as a double ("+" allowed). A number too small for a double (1e-400) is 0;
// one too large (1e400) is named as such.
Parsed parse_number(const std::string& cell, double& v) {
  const char* b = cell.data() + (!cell.empty() && cell[0] == '+');
  const char* e = cell.data() + cell.size();
  const auto res = std::from_chars(b, e, v);
  if (b == e || res.ptr != e) return Parsed::not_a_number;
  if (res.ec == std::errc::result_out_of_range) {
    v = std::strtod(std::string(b, e).c_str(), nullptr);  // 0 (underflow) or +-inf
    return std::isfinite(v) ? Parsed::number : Parsed::too_large;
  }
  return res.ec == std::errc() ? Parsed::number : Parsed::not_a_number;
}

std::vector<std::string> split_fields(const std::string& line, char separator) {
  std::vector<std::string> out;
  std::size_t pos = 0;
  for (;;) {
    const auto next = line.find(separator, pos);
    out.push_back(trim(line.substr(pos, next == std::string::npos ? std::string::npos : next - pos)));
    if (next == std::string::npos) return out;
    pos = next + 1;
  }
}

}  // namespace

Recording parse_csv(const std::string& text, const std::string& source) {
  Recording r;
  r.source = source;
  std::istringstream in(text);
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (!skipped(line)) break;
  }
  if (skipped(line)) throw InputError(source + ": empty file (a header line is expected)");
  const char separator = line.find(',') != std::string::npos   ? ','
                         : line.find(';') != std::string::npos ? ';'
                         : line.find('\t') != std::string::npos ? '\t'
                                                                : ',';
  const std::vector<std::string> first = split_fields(line, separator);
  bool header = false;
  for (const auto& cell : first) {
    double v = 0;
    const bool nan_text = cell == "nan" || cell == "NaN" || cell == "NAN" || cell == "-nan";
    header = header || !(nan_text || parse_number(cell, v) != Parsed::not_a_number);
  }
  if (header) {
    std::set<std::string> seen;
    for (const auto& cell : first) {
      const std::string where = source + ": line " + std::to_string(line_no) + ", column " +
                                std::to_string(r.names.size() + 1);
      if (cell.empty()) throw InputError(where + ": empty column name in the header");
      if (!seen.insert(cell).second)
        throw InputError(where + ": the column name \"" + printable(cell, 100) + "\" is given twice");
      r.names.push_back(cell);
    }
  } else {
    for (std::size_t c = 0; c < first.size(); ++c) r.names.push_back(std::to_string(c + 1));
  }
  r.columns.resize(r.names.size());
  const std::size_t nc = r.names.size();
  int row = 0;
  bool pending = !header;  // a header-less file: the first line is data
  while (pending || std::getline(in, line)) {
    if (!pending) ++line_no;
    pending = false;
    if (skipped(line)) continue;
    ++row;
    const std::vector<std::string> cells = split_fields(line, separator);
    if (cells.size() > nc)
      throw InputError(source + ": line " + std::to_string(line_no) + ": more than " + std::to_string(nc) +
                       " values (the header has " + std::to_string(nc) + " columns)");
    if (cells.size() < nc)
      throw InputError(source + ": line " + std::to_string(line_no) + ": " + std::to_string(cells.size()) +
                       " values, the header has " + std::to_string(nc) + " columns");
    for (std::size_t col = 0; col < nc; ++col) {
      const std::string& cell = cells[col];
      double v = 0;
      const bool nan_text = cell == "nan" || cell == "NaN" || cell == "NAN" || cell == "-nan";
      const auto place = [&] {
        return source + ": line " + std::to_string(line_no) + ", column " + std::to_string(col + 1) + " (\"" +
               printable(r.names[col], 100) + "\")";
      };
      const Parsed parsed = nan_text ? Parsed::number : parse_number(cell, v);
      if (nan_text) v = std::nan("");
      if (parsed == Parsed::too_large)
        throw InputError(place() + ": the number " + printable(cell, 40) + " is outside the range of double precision");
      if (parsed == Parsed::not_a_number) throw InputError(place() + ": not a number: \"" + printable(cell, 40) + "\"");
      if (!std::isfinite(v))
        throw InputError(source + ": data row " + std::to_string(row) + " (line " + std::to_string(line_no) +
                         "), column \"" + printable(r.names[col], 100) + "\": NaN or infinite value");
      r.columns[col].push_back(v);
    }
  }
  if (row == 0) throw InputError(source + ": no data rows after the header");
  return r;
}

Recording read_csv(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the data file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parse_csv(ss.str(), path);
}

namespace {

// matio reports through a log function; its default prints to stderr (bytes of the file
// included) and aborts on errors. Ours keeps quiet: read_mat says what went wrong.
void quiet_matio_log(int, char*) {}

// v7.3 (HDF5) files: matio and the HDF5 library. Not hardened like the level 4/5 reader: HDF5's
// own parser is trusted with the file (docs/reliability.md).
std::vector<Mat_vector> read_mat_v73_vectors(const std::string& bytes, const std::string& path) {
  static const char signature[] = "\x89HDF\r\n\x1a\n";
  if (bytes.size() < 520 || bytes.compare(512, 8, signature, 8) != 0)
    throw InputError(path + ": a v7.3 .mat header but no HDF5 data at byte 512");
  static std::once_flag log_once;
  std::call_once(log_once, [] { Mat_LogInitFunc("sets", quiet_matio_log); });
  mat_t* mat = Mat_Open(path.c_str(), MAT_ACC_RDONLY);
  if (!mat) throw InputError(path + ": cannot open as a MATLAB v7.3 .mat file");
  std::vector<Mat_vector> vars;
  std::vector<std::string> wanted;  // names of the real numeric vectors, from the headers alone
  while (matvar_t* v = Mat_VarReadNextInfo(mat)) {
    const bool numeric = v->class_type >= MAT_C_DOUBLE && v->class_type <= MAT_C_UINT64;
    if (numeric && !v->isComplex && v->rank == 2 && v->name && v->dims && (v->dims[0] == 1 || v->dims[1] == 1) &&
        v->dims[0] * v->dims[1] > 1 && v->dims[0] * v->dims[1] <= max_mat_elements)
      wanted.emplace_back(v->name);
    Mat_VarFree(v);
  }
  for (const auto& name : wanted) {
    matvar_t* v = Mat_VarRead(mat, name.c_str());
    if (!v) continue;
    const std::size_t n = v->dims[0] * v->dims[1];
    Mat_vector out{name, std::vector<double>(n)};
    bool ok = v->data != nullptr;
    for (std::size_t i = 0; i < n && ok; ++i) {
      switch (v->data_type) {
        case MAT_T_DOUBLE: out.values[i] = static_cast<const double*>(v->data)[i]; break;
        case MAT_T_SINGLE: out.values[i] = static_cast<const float*>(v->data)[i]; break;
        case MAT_T_UINT8: out.values[i] = static_cast<const std::uint8_t*>(v->data)[i]; break;
        case MAT_T_INT8: out.values[i] = static_cast<const std::int8_t*>(v->data)[i]; break;
        case MAT_T_UINT16: out.values[i] = static_cast<const std::uint16_t*>(v->data)[i]; break;
        case MAT_T_INT16: out.values[i] = static_cast<const std::int16_t*>(v->data)[i]; break;
        case MAT_T_UINT32: out.values[i] = static_cast<const std::uint32_t*>(v->data)[i]; break;
        case MAT_T_INT32: out.values[i] = static_cast<const std::int32_t*>(v->data)[i]; break;
        case MAT_T_UINT64: out.values[i] = static_cast<double>(static_cast<const std::uint64_t*>(v->data)[i]); break;
        case MAT_T_INT64: out.values[i] = static_cast<double>(static_cast<const std::int64_t*>(v->data)[i]); break;
        default: ok = false; break;
      }
    }
    if (ok) vars.push_back(std::move(out));
    Mat_VarFree(v);
  }
  Mat_Close(mat);
  return vars;
}

}  // namespace

Recording read_mat(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the data file");
  std::ostringstream ss;
  ss << in.rdbuf();
  const std::string bytes = ss.str();
  std::vector<Mat_vector> vars;
  switch (mat_format(bytes)) {
    case Mat_format::v5: vars = read_mat_v5_vectors(bytes, path); break;
    case Mat_format::v4: vars = read_mat_v4_vectors(bytes, path); break;
    case Mat_format::v73: vars = read_mat_v73_vectors(bytes, path); break;
    case Mat_format::unknown: throw InputError(path + ": not a MATLAB .mat file (too short)");
  }
  if (vars.empty()) throw InputError(path + ": no numeric vector variables in the .mat file");
  std::map<std::size_t, int> count;
  for (const auto& v : vars) ++count[v.values.size()];
  std::size_t n = 0;
  int best = 0;
  for (const auto& [len, c] : count)
    if (c > best) best = c, n = len;
  Recording r;
  r.source = path;
  for (auto& v : vars) {
    if (v.values.size() != n) continue;
    for (std::size_t i = 0; i < n; ++i)
      if (!std::isfinite(v.values[i]))
        throw InputError(path + ": variable \"" + printable(v.name, 64) + "\", sample " + std::to_string(i + 1) +
                         ": NaN or infinite value");
    r.add(v.name, std::move(v.values));
  }
  return r;
}

Recording read_recording(const std::string& path) {
  const auto dot = path.rfind('.');
  if (dot != std::string::npos && path.substr(dot) == ".mat") return read_mat(path);
  return read_csv(path);
}

void write_csv(const Recording& r, const std::string& path) {
  std::ostringstream out;
  out.precision(12);
  for (std::size_t c = 0; c < r.names.size(); ++c) out << (c ? "," : "") << r.names[c];
  out << "\n";
  for (int i = 0; i < r.rows(); ++i) {
    for (std::size_t c = 0; c < r.columns.size(); ++c) out << (c ? "," : "") << r.columns[c][i];
    out << "\n";
  }
  write_file_atomically(path, out.str());
}

}  // namespace sets
