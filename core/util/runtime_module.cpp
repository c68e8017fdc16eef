#include "util/runtime_module.hpp"

#include <dlfcn.h>

#include <boost/dll/runtime_symbol_info.hpp>
#include <mutex>
#include <stdexcept>

#include "util/directory_list.hpp"

namespace fibrodem {
namespace fs = std::filesystem;

namespace {

std::mutex& directories_mutex() {
  static std::mutex mutex;
  return mutex;
}

std::vector<fs::path>& added_directories() {
  static std::vector<fs::path> dirs;
  return dirs;
}

std::string file_name_of(const std::string& name) { return "libfibrodem-" + name + ".so"; }

// The executable or library this code is linked into. The loader names the
// executable as it was started (relative to the start's working directory,
// which may have changed since): that one is asked of the kernel instead.
fs::path binary_holding_this_code() {
  fs::path binary = boost::dll::this_line_location();
  if (binary.is_relative()) binary = boost::dll::program_location();
  return binary;
}

}  // namespace

void add_module_directory(const fs::path& dir) {
  const std::lock_guard lock(directories_mutex());
  added_directories().push_back(dir);
}

std::vector<fs::path> module_search_path() {
  std::vector<fs::path> path = directories_in_environment("FIBRODEM_MODULE_PATH");
  {
    const std::lock_guard lock(directories_mutex());
    path.insert(path.end(), added_directories().begin(), added_directories().end());
  }
  const fs::path beside = binary_holding_this_code().parent_path();
  path.push_back(beside);
  path.push_back(beside.parent_path());
  path.push_back(beside.parent_path() / "lib" / "fibrodem");
  return path;
}

void* module_entry(const std::string& name, const char* entry_symbol, const std::string& needed_for, bool global) {
  const std::string file = file_name_of(name);
  std::string searched;
  for (const fs::path& dir : module_search_path()) {
    const fs::path candidate = dir / file;
    searched += (searched.empty() ? "" : ", ") + dir.string();
    std::error_code ec;
    if (!fs::is_regular_file(candidate, ec)) continue;
    void* library = dlopen(candidate.c_str(), RTLD_NOW | (global ? RTLD_GLOBAL : RTLD_LOCAL));
    if (!library) throw std::runtime_error("cannot load " + candidate.string() + " (" + needed_for + "): " + dlerror());
    void* entry = dlsym(library, entry_symbol);
    if (!entry)
      throw std::runtime_error(candidate.string() + " has no entry point '" + entry_symbol + "' (" + needed_for +
                               "): it is not a module of this fibrodem; rebuild or reinstall fibrodem");
    return entry;
  }
  throw std::runtime_error("fibrodem's module " + file + " is missing (" + needed_for + "; looked in: " + searched +
                           "; set FIBRODEM_MODULE_PATH to add a directory, or rebuild/reinstall fibrodem)");
}

}  // namespace fibrodem
