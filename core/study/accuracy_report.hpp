// An accuracy ladder's results (study/accuracy_ladder.hpp) as files:
//   accuracy.csv        one row per run, the reference and its check first
//   accuracy.md         the table, and the cheapest run meeting each error
//                       level: APD90 error 10, 1, 0.1, 0.01 ms; V RMS error
//                       10, 1, 0.1, 0.01 mV; CV error 5, 1, 0.1 % when the
//                       scene has a CV
//   work_precision.png  APD90 and V RMS error against wall time, log-log
#pragma once

#include <filesystem>
#include <string>

#include "study/accuracy_ladder.hpp"

namespace fibrodem {

void write_accuracy_csv(const AccuracyLadder& ladder, const std::filesystem::path& file);
// `command`: how the ladder was asked for, quoted at the top.
std::string accuracy_markdown(const AccuracyLadder& ladder, const std::string& command);
void write_work_precision_png(const AccuracyLadder& ladder, const std::filesystem::path& file);

// The three files into folder `dir` (which must exist); returns accuracy.md's text.
std::string write_accuracy_report(const AccuracyLadder& ladder, const std::filesystem::path& dir,
                                  const std::string& command);

}  // namespace fibrodem
