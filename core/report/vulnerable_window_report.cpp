#include "report/vulnerable_window_report.hpp"

#include <fstream>
#include <stdexcept>

#include "io/csv_table.hpp"
#include "report/html_document.hpp"
#include "util/json_reader.hpp"

namespace fibrodem {

namespace fs = std::filesystem;

bool is_vulnerable_window_folder(const fs::path& dir) { return fs::is_regular_file(dir / "vulnerable_window.json"); }

namespace {

std::string text_of(const json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  return v.dump();
}

std::string window_text(const json& w) {
  std::string text = "[" + text_of(w.value("lower_ms", json())) + ", " + text_of(w.value("upper_ms", json())) + "] ms";
  if (w.value("open_below", false)) text += ", open below (re-entry at the scan's first interval)";
  if (w.value("open_above", false)) text += ", open above (re-entry at the scan's last interval)";
  return text;
}

void windows_section(HtmlDocument& page, const json& search) {
  std::vector<std::string> overall;
  for (const auto& w : search.value("overall", json::array())) overall.push_back(window_text(w));
  if (overall.empty()) page.notice("info", "no re-entry at any interval run", {});
  else page.notice("ok", "vulnerable window" + std::string(overall.size() > 1 ? "s" : "") + " (any seed)", overall);
  if (search.value("failed", 0) > 0)
    page.notice("error", text_of(search["failed"]) + " run(s) did not complete (counted as not induced)", {});
  if (search.contains("note")) page.notice("info", "note", {text_of(search["note"])});

  const json scan = search.value("scan", json::object());
  page.definition_list({{"scan", text_of(scan.value("from_ms", json())) + " to " + text_of(scan.value("to_ms", json())) +
                                     " ms by " + text_of(scan.value("step_ms", json())) + " ms"},
                        {"bisection resolution", text_of(scan.value("resolution_ms", json())) + " ms"},
                        {"last S1 onset", text_of(search.value("s1_last_onset_ms", json())) + " ms"},
                        {"capture fraction", text_of(search.value("capture_fraction", json()))},
                        {"runs", text_of(search.value("runs", json()))}});
  page.heading(2, "Windows per seed", "windows");
  page.paragraph("Each window's bounds are its first and last induced interval, each within the resolution of the "
                 "nearest interval that is not induced.");
  std::vector<std::vector<std::string>> rows;
  for (const auto& s : search.value("per_seed", json::array())) {
    const json windows = s.value("windows", json::array());
    if (windows.empty()) rows.push_back({text_of(s.value("seed", json())), "", "", "none"});
    for (const auto& w : windows)
      rows.push_back({text_of(s.value("seed", json())), text_of(w.value("lower_ms", json())),
                      text_of(w.value("upper_ms", json())),
                      std::string(w.value("open_below", false) ? "open below " : "") +
                          (w.value("open_above", false) ? "open above" : "")});
  }
  page.table({"seed", "lower (ms)", "upper (ms)", "remark"}, rows);
}

// Every run, in interval order per seed (vulnerable_window.csv), with
// whether S2 induced re-entry, and links to the runs' folders.
void runs_section(HtmlDocument& page, const fs::path& dir) {
  page.heading(2, "S2 at each coupling interval", "runs");
  const auto table = read_csv_table(dir / "vulnerable_window.csv");
  const auto outcome = table ? table->column("outcome") : std::nullopt;
  const auto run = table ? table->column("run") : std::nullopt;
  if (!outcome || !run) {
    page.paragraph("vulnerable_window.csv is missing or has no outcome column.");
    return;
  }
  std::vector<std::string> header = table->header;
  header.insert(header.begin() + static_cast<long>(*outcome) + 1, "induced");
  std::vector<std::vector<std::string>> rows;
  std::string links;
  for (const auto& row : table->rows) {
    rows.push_back(row);
    rows.back().insert(rows.back().begin() + static_cast<long>(*outcome) + 1, row[*outcome] == "reentry" ? "yes" : "no");
    // Its report.html where the run wrote one (the search's runs write none by default), else its summary.json.
    for (const char* file : {"report.html", "summary.json"}) {
      if (row[*run].empty() || !fs::exists(dir / row[*run] / file)) continue;
      links += (links.empty() ? "" : ", ") + std::string("<a href=\"") + html_escape(row[*run]) + "/" + file +
               "\">" + html_escape(row[*run]) + "</a>";
      break;
    }
  }
  page.table(header, rows);
  if (!links.empty()) page.raw("<p>Each run: " + links + "</p>\n");
}

}  // namespace

fs::path write_vulnerable_window_report(const fs::path& dir) {
  std::ifstream in(dir / "vulnerable_window.json");
  if (!in) throw std::runtime_error("no " + (dir / "vulnerable_window.json").string());
  json search;
  try {
    search = json::parse(in);
  } catch (const json::exception& e) {
    throw std::runtime_error((dir / "vulnerable_window.json").string() + " cannot be read: " + e.what());
  }
  const fs::path name = dir.filename().empty() ? dir.parent_path().filename() : dir.filename();  // "out/x/"
  HtmlDocument page("fibrodem vulnerable window: " + name.string());
  windows_section(page, search);
  page.png_figure("Outcome of S2 and activity after it against the coupling interval", dir / "vulnerable_window.png");
  runs_section(page, dir);
  const fs::path file = dir / "report.html";
  page.write(file);
  return file;
}

}  // namespace fibrodem
