// report.html of a vulnerable-window search's folder (`fibrodem
// vulnerable-window`, docs/topics/arrhythmia.md): the windows found (bisected
// bounds per seed and over the seeds), the outcome of S2 at every interval
// run (induced or not), the search's plot and links to each run (its report.html, else its
// summary.json).
// Written from the folder's files alone (vulnerable_window.json, .csv, .png),
// as a run's report is from its own.
#pragma once

#include <filesystem>

namespace fibrodem {

// Whether dir holds a search's results (vulnerable_window.json).
bool is_vulnerable_window_folder(const std::filesystem::path& dir);

// Writes dir/report.html; returns its path. std::runtime_error if
// vulnerable_window.json is missing or unreadable, or the page cannot be written.
std::filesystem::path write_vulnerable_window_report(const std::filesystem::path& dir);

}  // namespace fibrodem
