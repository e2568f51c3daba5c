#include "common/cli.hpp"

#include <signal.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iostream>

#include "common/gnuplot.hpp"
#include "sets/core/atomic_file.hpp"
#include "sets/core/error.hpp"
#include "sets/core/exit_code.hpp"

namespace sets::app {

namespace fs = std::filesystem;

namespace {

// ---------------------------------------------------------------- numbers, whole or not at all

std::string whole_float(const std::string& s) {
  const char* first = s.data() + (!s.empty() && s[0] == '+');
  const char* last = s.data() + s.size();
  double v = 0;
  const auto [ptr, ec] = std::from_chars(first, last, v, std::chars_format::general);
  if (first == last || ptr != last || (ec != std::errc() && ec != std::errc::result_out_of_range))
    return "'" + s + "' is not a number";
  if (ec == std::errc::result_out_of_range) return "'" + s + "' is out of the range of double";
  if (!std::isfinite(v)) return "'" + s + "' is not a finite number";
  return {};
}

// Decimal digits with an optional sign; leading zeros are dropped so that CLI11 (strtoll with
// base 0) does not read "010" as octal.
std::string whole_integer(std::string& s, bool allow_sign) {
  std::size_t i = !s.empty() && (s[0] == '+' || (allow_sign && s[0] == '-'));
  if (i == s.size() || s.find_first_not_of("0123456789", i) != std::string::npos)
    return "'" + s + "' is not a whole " + std::string(allow_sign ? "number" : "non-negative number");
  const std::size_t nz = s.find_first_not_of('0', i);
  std::string digits = nz == std::string::npos ? std::string("0") : s.substr(nz);
  if (s[0] == '-') digits.insert(digits.begin(), '-');
  s = std::move(digits);
  return {};
}

// ---------------------------------------------------------------- signals


void on_signal(int sig) {
  stop_gnuplot();
  remove_pending_temporaries();
  ::signal(sig, SIG_DFL);
  ::raise(sig);
}

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGHUP}) ::sigaction(sig, &sa, nullptr);
}

std::string folder_problem(const fs::path& folder) {
  std::error_code ec;
  const auto st = fs::status(folder, ec);
  if (!fs::exists(st)) return "the folder " + folder.string() + " does not exist";
  if (!fs::is_directory(st)) return folder.string() + " is not a folder";
  if (::access(folder.c_str(), W_OK | X_OK) != 0) return "the folder " + folder.string() + " is not writable";
  return {};
}

}  // namespace

Cli::Cli(std::string name, std::string description) : name_(std::move(name)), app_(std::move(description)) {}

CLI::Option* Cli::add_output_file(const std::string& flag, std::string& path, const std::string& help) {
  outputs_.push_back({flag, &path, false, {}});
  return app_.add_option(flag, path, help);
}

CLI::Option* Cli::add_output_folder(const std::string& flag, std::string& path, const std::string& help,
                                    const std::string& owned) {
  outputs_.push_back({flag, &path, true, owned});
  return app_.add_option(flag, path, help);
}

void Cli::check_numbers() {
  // transform() puts these checks before the option's own (ranges, ...), so a malformed number is
  // reported as such; they may rewrite the text (leading zeros of integers).
  for (CLI::Option* opt : app_.get_options()) {
    const std::string type = opt->get_type_name();
    const auto is = [&](const char* t) { return type.rfind(t, 0) == 0; };
    if (is("FLOAT"))
      opt->transform(CLI::Validator([](std::string& s) { return whole_float(s); }, "", ""));
    else if (is("INT"))
      opt->transform(CLI::Validator([](std::string& s) { return whole_integer(s, true); }, "", ""));
    else if (is("UINT"))
      opt->transform(CLI::Validator([](std::string& s) { return whole_integer(s, false); }, "", ""));
  }
}

void Cli::check_outputs() {
  for (const Output& o : outputs_) {
    if (o.path->empty()) continue;
    // "report/" names the folder "report" (as the shell's completion writes it): without the
    // separator, not a path with an empty file name whose staging folder would sit inside it.
    if (o.folder)
      while (o.path->size() > 1 && o.path->back() == fs::path::preferred_separator) o.path->pop_back();
    const fs::path target(*o.path);
    const fs::path folder = target.parent_path().empty() ? fs::path(".") : target.parent_path();
    const auto fail = [&](const std::string& why) {
      throw InputError(o.flag + " " + *o.path + ": cannot write there: " + why);
    };
    if (target.filename().empty() || target.filename() == "." || target.filename() == "..")
      fail("give a " + std::string(o.folder ? "folder" : "file") + " name");
    if (const std::string why = folder_problem(folder); !why.empty()) fail(why);
    std::error_code ec;
    const auto st = fs::symlink_status(target, ec);
    if (!fs::exists(st)) continue;
    if (!o.folder) {
      if (fs::is_directory(st)) fail("it is a folder");
      continue;
    }
    if (!fs::is_directory(st)) fail("it exists and is not a folder");
    const std::regex owned(o.owned);
    for (const auto& e : fs::directory_iterator(target, ec)) {
      const std::string n = e.path().filename().string();
      if (!std::regex_match(n, owned))
        fail("the folder exists and holds '" + n + "', which " + name_ +
             " does not write (it replaces the folder as a whole): give a new or empty folder");
    }
  }
}

std::optional<int> Cli::parse(int argc, char** argv) {
  check_numbers();
  try {
    app_.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app_.exit(e) == 0 ? exit_success : exit_bad_input;
  }
  try {
    check_outputs();
  } catch (const std::exception& e) {
    return report_failure(name_.c_str(), e);
  }
  install_signal_handlers();
  return std::nullopt;
}

int Cli::run(const std::function<int()>& body) const {
  try {
    return body();
  } catch (const std::exception& e) {
    return report_failure(name_.c_str(), e);
  }
}

std::vector<std::string> split_list(const std::string& text) {
  std::vector<std::string> out;
  std::size_t pos = 0;
  for (;;) {
    const auto comma = text.find(',', pos);
    std::string item = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    const auto a = item.find_first_not_of(" \t"), b = item.find_last_not_of(" \t");
    out.push_back(a == std::string::npos ? std::string() : item.substr(a, b - a + 1));
    if (comma == std::string::npos) return out;
    pos = comma + 1;
  }
}

}  // namespace sets::app
