#pragma once
// Flags of every app, and the exit-code contract of docs/contributing.md enforced in one place:
//  - any usage error exits 1 (never CLI11's own codes), --help exits 0;
//  - every number is parsed whole ("0.5abc", "12:30", "0x10" are rejected with the flag named),
//    integers in decimal, and NaN or infinite values are rejected for every floating-point flag;
//  - every output path (file or folder) is checked right after parsing, before any work;
//  - SIGINT/SIGTERM/SIGHUP remove the temporaries in progress (sets/core/atomic_file.hpp) and
//    stop a running gnuplot before the app ends with the signal;
//  - an exception that ends the app is reported once and mapped by sets::report_failure.

#include <CLI/CLI.hpp>

#include <functional>
#include <optional>
#include <regex>
#include <string>
#include <vector>

namespace sets::app {

class Cli {
 public:
  Cli(std::string name, std::string description);

  CLI::App& app() { return app_; }
  const std::string& name() const { return name_; }

  /// An output file: its folder must exist and be writable, and the path must not be a folder.
  CLI::Option* add_output_file(const std::string& flag, std::string& path, const std::string& help);
  /// An output folder, written as a whole (sets::AtomicDirectory): its parent folder must exist and
  /// be writable; an existing folder may only hold files whose names match `owned` (what the app
  /// writes there), so that replacing it never deletes anything else.
  CLI::Option* add_output_folder(const std::string& flag, std::string& path, const std::string& help,
                                 const std::string& owned);

  /// Parses the command line, then checks the output paths. Returns the exit code to end with now
  /// (0 after --help, 1 for any usage error or unusable output path), or nothing to go on.
  std::optional<int> parse(int argc, char** argv);

  /// Runs the app's work; an exception that ends it is printed and mapped to its exit code.
  int run(const std::function<int()>& body) const;

 private:
  struct Output {
    std::string flag;
    std::string* path;
    bool folder;
    std::string owned;
  };
  void check_numbers();
  void check_outputs();  // also drops a folder path's trailing separators

  std::string name_;
  CLI::App app_;
  std::vector<Output> outputs_;
};

/// Splits "a,b,c" at commas, trimming blanks around every item (empty items are kept).
std::vector<std::string> split_list(const std::string& text);

}  // namespace sets::app
