#include "cellml/import.hpp"

#include <fstream>
#include <random>
#include <regex>

#include "cellml/import_error.hpp"
#include "cellml/model_analysis.hpp"
#include "cellml/plugin_writer.hpp"
#include "cellml/units_check.hpp"

namespace fibrodem::cellml {

namespace fs = std::filesystem;

namespace {

void write_file(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw ImportError(path.string() + ": cannot be written");
}

}  // namespace

ImportResult import_cellml(const ImportOptions& o) {
  if (!std::regex_match(o.name, std::regex("[A-Za-z_][A-Za-z0-9_]*")))
    throw ImportError("--name '" + o.name + "': expected a plugin name of letters, digits and '_'");
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
  // Inconsistent units in an equation: the numbers would be used at a scale
  // (or dimension) the author did not mean; refused at the first.
  if (const auto issues = check_equation_units(model); !issues.empty())
    throw ImportError(issues.front().path + ": inconsistent units: " + issues.front().message +
                      (issues.size() > 1 ? " (and " + std::to_string(issues.size() - 1) + " more)" : ""));
  const GeneratedPlugin plugin = write_plugin(model, w);

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
  return {folder, plugin.notes};
}

}  // namespace fibrodem::cellml
