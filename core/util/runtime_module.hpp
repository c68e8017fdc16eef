// Optional parts of fibrodem built as shared modules (modules/) and opened on
// first use, so that a process which never draws or never runs under mpirun
// does not load Cairo or Open MPI and their dozens of libraries at start-up
// (docs/topics/performance.md#start-up).
//
// A module `name` is the file libfibrodem-NAME.so (a hyphen, so the plugin
// registry's libfibrodem_* never takes it for a cell model), searched in:
// every directory of $FIBRODEM_MODULE_PATH (':'-separated), the directories
// added with add_module_directory(), then beside the binary holding this code
// (the `fibrodem` executable, or a library linking the core), its parent
// folder, and ../lib/fibrodem (where `cmake --install` puts the modules).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace fibrodem {

// A directory searched before the binary's own (the Python module adds the
// build's folder, where its modules are).
void add_module_directory(const std::filesystem::path& dir);

std::vector<std::filesystem::path> module_search_path();

// The address of `entry_symbol` in module `name`, opened (once; it stays
// loaded). `global`: its symbols are made visible to the libraries it loads
// in turn (Open MPI opens its components against libmpi's symbols).
// Throws std::runtime_error naming the file, the directories searched and
// what the module is needed for, if it is missing or lacks the symbol.
void* module_entry(const std::string& name, const char* entry_symbol, const std::string& needed_for,
                   bool global = false);

// The object behind a module's interface T: its entry `entry_symbol` is a
// function `const T* ()`, called here. Callers keep the result (a static at
// their one place of use), so the module is opened on first use only.
template <class T>
const T& module_object(const std::string& name, const char* entry_symbol, const std::string& needed_for) {
  using Entry = const T* (*)();
  return *reinterpret_cast<Entry>(module_entry(name, entry_symbol, needed_for))();
}

}  // namespace fibrodem
