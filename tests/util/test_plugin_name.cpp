// A plugin's name follows one rule in the three places that check it:
// `fibrodem new-model`, `fibrodem import-cellml` (core/util/plugin_name.hpp) and
// the SDK's fibrodem_add_cell_model / fibrodem_add_contact_law
// (cmake/FibrodemPlugin.cmake). The expected verdicts come from what a name
// becomes: a C++ class name that is not reserved (no leading '_', [lex.name]),
// a file and CMake target name without separators or spaces, at most 64
// characters.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include "util/plugin_name.hpp"

namespace fs = std::filesystem;

namespace {

struct NameCase {
  std::string name;
  bool valid;
};

const NameCase kNames[] = {
    {"colman", true},
    {"deckerA", true},  // mixed case: a CellML model's own name, kept
    {"Decker2009", true},
    {"my_model_2", true},
    {"x", true},
    {std::string(64, 'a'), true},
    {std::string(65, 'a'), false},  // past 64 characters
    {"", false},
    {"_decker", false},      // a leading '_': reserved in C++ at global scope
    {"2decker", false},      // not an identifier
    {"decker-2009", false},  // '-': not in a C++ identifier
    {"decker 2009", false},
    {"decker.so", false},
    {"../decker", false},  // a path, not a name
    {"d\xc3\xa9" "cker", false},  // non-ASCII letter
};

const std::string kFibrodem = std::string(FIBRODEM_BINARY_DIR) + "/fibrodem";

// Runs `command` in a shell; its exit status, its standard error in `err`.
int run(const std::string& command, const fs::path& err_file, std::string& err) {
  const int status = std::system((command + " > /dev/null 2> '" + err_file.string() + "'").c_str());
  std::ifstream in(err_file);
  std::stringstream text;
  text << in.rdbuf();
  err = text.str();
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// `text` with each run of white space made one space (CMake wraps its messages).
std::string one_line(const std::string& text) {
  std::string out;
  for (char c : text) {
    const bool space = c == ' ' || c == '\n' || c == '\t';
    if (!space) out += c;
    else if (!out.empty() && out.back() != ' ') out += ' ';
  }
  return out;
}

// A fresh, empty directory under the system's temporary directory.
fs::path fresh_dir(const std::string& tag) {
  const fs::path dir = fs::temp_directory_path() / ("fibrodem_plugin_name_" + tag + "_" +
                                                    std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

}  // namespace

TEST_CASE("plugin names: letters of either case, digits and '_', starting with a letter, at most 64") {
  for (const auto& c : kNames) {
    CAPTURE(c.name);
    CHECK(fibrodem::valid_plugin_name(c.name) == c.valid);
  }
}

TEST_CASE("plugin names: the SDK's CMake check gives the same verdict as the C++ rule") {
  const fs::path dir = fresh_dir("cmake");
  const std::string script = std::string(FIBRODEM_SOURCE_DIR) + "/cmake/FibrodemPlugin.cmake";
  for (const auto& c : kNames) {
    CAPTURE(c.name);
    std::string err;
    const int code = run("cmake -D 'name=" + c.name + "' -P '" + script + "'", dir / "err.txt", err);
    CHECK((code == 0) == c.valid);
    if (!c.valid) {
      CHECK(one_line(err).find("fibrodem plugin name '" + c.name + "'") != std::string::npos);
      CHECK(one_line(err).find(std::string("expected ") + fibrodem::kPluginNameRule) != std::string::npos);
    }
  }
  fs::remove_all(dir);
}

TEST_CASE("plugin names: new-model and import-cellml take deckerA and refuse _decker, naming value and rule") {
  const fs::path dir = fresh_dir("commands");
  const std::string cellml = std::string(FIBRODEM_SOURCE_DIR) + "/tests/cellml/hh_1952_1_0.cellml";
  std::string err;

  CHECK(run(kFibrodem + " new-model deckerA --dir '" + (dir / "new_ok").string() + "'", dir / "err.txt", err) == 0);
  CHECK(fs::exists(dir / "new_ok" / "deckerA.cpp"));
  CHECK(run(kFibrodem + " import-cellml '" + cellml + "' --name deckerA --out '" + (dir / "import_ok").string() + "'",
            dir / "err.txt", err) == 0);
  CHECK(fs::exists(dir / "import_ok" / "deckerA.cpp"));

  CHECK(run(kFibrodem + " new-model _decker --dir '" + (dir / "new_bad").string() + "'", dir / "err.txt", err) == 2);
  CHECK(err.find("'_decker'") != std::string::npos);
  CHECK(err.find(fibrodem::kPluginNameRule) != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "new_bad"));
  CHECK(run(kFibrodem + " import-cellml '" + cellml + "' --name _decker --out '" + (dir / "import_bad").string() + "'",
            dir / "err.txt", err) == 5);
  CHECK(err.find("--name '_decker'") != std::string::npos);
  CHECK(err.find(fibrodem::kPluginNameRule) != std::string::npos);
  CHECK_FALSE(fs::exists(dir / "import_bad"));
  fs::remove_all(dir);
}
