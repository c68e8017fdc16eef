// `fibrodem new-model NAME [--kind ionic|myofilament|contact-law] [--dir DIR]`:
// writes a working, commented plugin skeleton (source, CMakeLists.txt for an
// out-of-tree build against an installed fibrodem, a test manifest) into DIR
// (default ./NAME). Refuses to overwrite anything.
#include <filesystem>
#include <fstream>
#include <iostream>

#include "apps/commands.hpp"
#include "apps/new_model_templates.hpp"
#include "util/plugin_name.hpp"

namespace fibrodem::cli {

namespace fs = std::filesystem;

namespace {

std::string replace_all(std::string text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
    text.replace(at, from.size(), to);
  return text;
}

// my_model -> MyModel; a name the skeleton declares beside the class (its
// enums of indices: state -> State) gets the kind's word after it
// (StateModel, ParamLaw), which would not compile otherwise.
std::string class_name(const std::string& name, const std::string& kind) {
  std::string out;
  bool upper = true;
  for (char c : name) {
    if (c == '_') {
      upper = true;
      continue;
    }
    out += upper ? static_cast<char>(std::toupper(static_cast<unsigned char>(c))) : c;
    upper = false;
  }
  for (const char* declared : {"State", "Param", "Input", "Output"})
    if (out == declared) return out + (kind == "contact-law" ? "Law" : "Model");
  return out;
}

}  // namespace

int new_model_command(const NewModelArgs& args) {
  if (!valid_plugin_name(args.name)) {
    std::cerr << "error: model name '" << args.name << "': expected " << kPluginNameRule << "\n";
    return 2;
  }
  const char* source = nullptr;
  const char* manifest = nullptr;
  const char* add_function = "fibrodem_add_cell_model";
  if (args.kind == "ionic") {
    source = templates::kIonicSource;
    manifest = templates::kIonicManifest;
  } else if (args.kind == "myofilament") {
    source = templates::kMyofilamentSource;
    manifest = templates::kMyofilamentManifest;
  } else if (args.kind == "contact-law") {
    source = templates::kContactLawSource;
    manifest = templates::kContactLawManifest;
    add_function = "fibrodem_add_contact_law";
  } else {
    std::cerr << "error: --kind '" << args.kind << "': expected ionic, myofilament or contact-law\n";
    return 2;
  }
  const fs::path dir = args.dir.empty() ? fs::path(args.name) : fs::path(args.dir);
  const std::vector<std::pair<fs::path, std::string>> files = {
      {dir / (args.name + ".cpp"), source},
      {dir / "CMakeLists.txt", templates::kCMakeLists},
      {dir / (args.name + "_test.json"), manifest},
  };
  for (const auto& [file, text] : files) {
    std::error_code ec;
    if (fs::exists(file, ec)) {
      std::cerr << "error: " << file.string() << " exists; new-model writes only new files (choose another --dir)\n";
      return 2;
    }
  }
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) {
    std::cerr << "error: cannot create " << dir.string() << ": " << ec.message() << "\n";
    return 2;
  }
  for (const auto& [file, text] : files) {
    std::string out = replace_all(text, "@NAME@", args.name);
    out = replace_all(out, "@CLASS@", class_name(args.name, args.kind));
    out = replace_all(out, "@KIND@", args.kind);
    out = replace_all(out, "@ADD_FUNCTION@", add_function);
    out = replace_all(out, "@TARGET@", (args.kind == "contact-law" ? "fibrodem_contact_law_" : "fibrodem_") + args.name);
    std::ofstream stream(file);
    stream << out;
    if (!stream.flush()) {
      std::cerr << "error: cannot write " << file.string() << "\n";
      return 2;
    }
  }
  std::cout << "wrote " << args.kind << " plugin skeleton '" << args.name << "' in " << dir.string() << ":\n";
  for (const auto& [file, text] : files) std::cout << "  " << file.filename().string() << "\n";
  std::cout << "build it against an installed fibrodem:\n"
            << "  cmake -S " << dir.string() << " -B " << (dir / "build").string()
            << " -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=<fibrodem's install prefix>\n"
            << "  cmake --build " << (dir / "build").string() << " && ctest --test-dir " << (dir / "build").string()
            << "\n";
  return 0;
}

}  // namespace fibrodem::cli
