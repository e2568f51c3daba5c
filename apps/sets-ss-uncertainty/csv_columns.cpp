#include "csv_columns.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <sstream>

#include "sets/core/error.hpp"

namespace {

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : line) {
    if (c == ',' || c == ';' || c == '\t') {
      out.push_back(cur);
      cur.clear();
    } else if (c != '\r') {
      cur += c;
    }
  }
  out.push_back(cur);
  for (auto& s : out) {
    const auto b = s.find_first_not_of(' ');
    const auto e = s.find_last_not_of(' ');
    s = b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
  }
  return out;
}

bool parse_double(const std::string& s, double& v) {
  if (s.empty()) return false;
  const char* first = s.data();
  if (*first == '+') ++first;
  const auto res = std::from_chars(first, s.data() + s.size(), v);
  return res.ec == std::errc() && res.ptr == s.data() + s.size();
}

}  // namespace

CsvTable read_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw sets::InputError(path + ": cannot open the file");
  CsvTable t;
  std::vector<std::vector<double>> rows;
  std::string line;
  int lineno = 0;
  std::size_t width = 0;
  while (std::getline(in, line)) {
    ++lineno;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[0] == '#') continue;
    const auto fields = split(line);
    std::vector<double> v(fields.size());
    bool numeric = true;
    for (std::size_t c = 0; c < fields.size() && numeric; ++c) numeric = parse_double(fields[c], v[c]);
    if (!numeric && rows.empty() && t.header.empty()) {
      t.header = fields;
      width = fields.size();
      continue;
    }
    if (width == 0) width = fields.size();
    if (fields.size() != width)
      throw sets::InputError(path + ":" + std::to_string(lineno) + ": " + std::to_string(fields.size()) +
                             " fields, expected " + std::to_string(width));
    for (std::size_t c = 0; c < fields.size(); ++c)
      if (!parse_double(fields[c], v[c]))
        throw sets::InputError(path + ":" + std::to_string(lineno) + ": column " + std::to_string(c + 1) +
                               (t.header.size() > c ? " (" + t.header[c] + ")" : std::string()) + ": '" +
                               fields[c] + "' is not a number");
    rows.push_back(std::move(v));
  }
  if (rows.empty()) throw sets::InputError(path + ": no data rows");
  t.data.resize(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(width));
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t c = 0; c < width; ++c) t.data(r, c) = rows[r][c];
  return t;
}

std::vector<int> parse_columns(const std::string& spec, const CsvTable& t, const std::string& flag) {
  std::vector<int> cols;
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto b = item.find_first_not_of(' ');
    item = b == std::string::npos ? std::string() : item.substr(b, item.find_last_not_of(' ') - b + 1);
    int idx = -1;
    const auto it = std::find(t.header.begin(), t.header.end(), item);
    if (it != t.header.end()) {
      idx = static_cast<int>(it - t.header.begin());
    } else {
      int k = 0;
      const auto res = std::from_chars(item.data(), item.data() + item.size(), k);
      if (res.ec != std::errc() || res.ptr != item.data() + item.size() || k < 1 || k > t.data.cols())
        throw sets::InputError(flag + ": '" + item + "' is neither a header name nor a column number in 1.." +
                               std::to_string(t.data.cols()));
      idx = k - 1;
    }
    cols.push_back(idx);
  }
  if (cols.empty()) throw sets::InputError(flag + ": no columns given");
  return cols;
}
