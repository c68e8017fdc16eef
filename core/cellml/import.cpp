#include "cellml/import.hpp"

#include <fstream>
#include <random>

#include "cellml/import_error.hpp"
#include "cellml/model_analysis.hpp"
#include "cellml/plugin_writer.hpp"
#include "cellml/units_check.hpp"
#include "util/plugin_name.hpp"

namespace fibrodem::cellml {

namespace fs = std::filesystem;

namespace {

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw ImportError(path.string() + ": cannot be written");
}

// The generated source with the unit warnings appended to its header (the
// leading comment block), one per line so that each can be found by grep.
std::string with_unit_warnings(const std::string& cpp, const std::vector<std::string>& warnings) {
  if (warnings.empty()) return cpp;
  std::string block = "//\n// Unit inconsistencies in the CellML (" + std::to_string(warnings.size()) +
                      "), imported with the numbers as written (no conversion\n"
                      "// factor inside an equation; `--strict-units` refuses them; see docs/topics/cellml_units.md):\n";
  for (const auto& w : warnings) block += "//   - " + w + "\n";
  std::size_t end = 0;  // the first line that is not a comment
  while (end < cpp.size() && cpp.compare(end, 2, "//") == 0) {
    const auto next = cpp.find('\n', end);
    end = next == std::string::npos ? cpp.size() : next + 1;
  }
  return cpp.substr(0, end) + block + cpp.substr(end);
}

}  // namespace

ImportResult import_cellml(const ImportOptions& o) {
  if (!valid_plugin_name(o.name))
    throw ImportError("--name '" + o.name + "': expected " + kPluginNameRule);
  if (o.kind != "ionic" && o.kind != "myofilament")
    throw ImportError("--kind '" + o.kind + "': expected ionic or myofilament");
  WriterOptions w;
  w.name = o.name;
  w.myofilament = o.kind == "myofilament";
  w.voltage = o.voltage;
  w.stimulus = o.stimulus;
  w.source_name = o.input.filename().string();
  for (const auto& m : o.map) {
    const auto eq = m.find('=');
    if (eq == std::string::npos || eq == 0)
      throw ImportError("--map '" + m + "': expected SIGNAL=component.variable");
    w.map[m.substr(0, eq)] = m.substr(eq + 1);
  }
  const Model model = analyse(read_cellml(o.input));
  // Inconsistent units inside an equation: public models hold such slips and
  // other tools import them with the numbers as written (CellML does not
  // require dimensional consistency), so they are warnings unless
  // --strict-units; every one is listed either way. So is an initial value
  // that names a constant of another dimension.
  std::vector<std::string> warnings = model.initial_value_unit_issues;
  for (const auto& issue : check_equation_units(model)) warnings.push_back(issue.text());
  if (o.strict_units && !warnings.empty()) {
    std::string all = "--strict-units: " + std::to_string(warnings.size()) + " unit inconsistenc" +
                      (warnings.size() == 1 ? "y" : "ies") + " in the equations:";
    for (const auto& warning : warnings) all += "\n  " + warning;
    throw ImportError(all);
  }
  GeneratedPlugin plugin = write_plugin(model, w);
  plugin.cpp = with_unit_warnings(plugin.cpp, warnings);

  const fs::path folder = o.out.empty() ? fs::path(o.name) : o.out;
  if (fs::exists(folder) && !o.overwrite)
    throw ImportError(folder.string() + " exists; choose another --out or pass --overwrite");
  // Write beside the target, then rename: a failure leaves no half plugin.
  const fs::path parent = fs::absolute(folder).parent_path();
  fs::create_directories(parent);
  std::random_device random;
  const fs::path staging = parent / ("." + folder.filename().string() + ".importing-" + std::to_string(random()));
  try {
    fs::create_directory(staging);
    write_file(staging / (o.name + ".cpp"), plugin.cpp);
    write_file(staging / "CMakeLists.txt", plugin.cmake);
    if (fs::exists(folder)) {
      const fs::path old = parent / ("." + folder.filename().string() + ".replaced-" + std::to_string(random()));
      fs::rename(folder, old);
      fs::rename(staging, folder);
      fs::remove_all(old);
    } else {
      fs::rename(staging, folder);
    }
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    throw;
  }
  return {folder, plugin.notes, warnings};
}

}  // namespace fibrodem::cellml
