#pragma once
// sets-diagnose's --report folder and --suite table (the diagnosis engineer's outputs; the app's
// main only parses flags and calls them).

#include <string>

#include "sets/diagnosis/diagnosis.hpp"

/// Writes index.html, plots (PNG via gnuplot), report.txt and augmented_model.json into `dir` as a whole:
/// everything is made in a hidden folder beside it and renamed into place at the end.
void write_report(const sets::Diagnosis& d, const std::string& dir, const std::string& augmented_text);

/// The files write_report writes (a regular expression over file names).
inline constexpr const char* kReportFiles = R"((index\.html|report\.txt|augmented_model\.json|signals_[a-z]+\.png|signature\.png))";

/// Diagnoses the fixed suite (every plant, or only `plant`, whose full report then goes to stderr)
/// or `count` random plants from `seed` (sets/examples/diagnosis_suite.hpp) and prints the scores
/// (markdown); one progress line per plant on stderr unless `quiet`. options.threads plants at once.
void print_suite(const std::string& kind, const std::string& plant, int count, unsigned seed,
                 const sets::DiagnosisOptions& options, bool quiet);
