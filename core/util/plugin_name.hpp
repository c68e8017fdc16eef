// What a plugin's name may be: the rule `fibrodem new-model` and
// `fibrodem import-cellml` check, and the same one cmake/FibrodemPlugin.cmake
// (fibrodem_add_cell_model, fibrodem_add_contact_law) applies.
//
// A name becomes a file name (libfibrodem_NAME.so, NAME.cpp), a CMake target
// (fibrodem_NAME), the model's name in manifests, and, after `new-model`
// turns my_model into MyModel, a C++ class name. ASCII letters of either case,
// digits and '_', starting with a letter, fit all four: a C++ identifier
// that is never reserved (no leading '_'), a portable file name, a CMake
// target name. 64 characters at most keeps the file names short.
#pragma once

#include <cstddef>
#include <string_view>

namespace fibrodem {

inline constexpr std::size_t kPluginNameMaxLength = 64;
inline constexpr const char* kPluginNameRule =
    "ASCII letters, digits and '_', starting with a letter, at most 64 characters";

inline bool valid_plugin_name(std::string_view name) {
  const auto letter = [](char c) { return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z'); };
  if (name.empty() || name.size() > kPluginNameMaxLength || !letter(name.front())) return false;
  for (char c : name)
    if (!letter(c) && !(c >= '0' && c <= '9') && c != '_') return false;
  return true;
}

}  // namespace fibrodem
