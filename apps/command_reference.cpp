// docs/reference/command_line.md, written from the command line's own
// declarations: every command with its description, a usage line and a table
// of its arguments and options (their help strings, as --help gives them),
// and the prose of apps/command_prose.cpp around them.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cctype>
#include <set>
#include <sstream>
#include <stdexcept>

#include "apps/command_reference.hpp"

namespace fibrodem::cli {

namespace {

std::vector<const CLI::App*> subcommands_of(const CLI::App& app) {
  return app.get_subcommands([](const CLI::App*) { return true; });
}

std::vector<const CLI::Option*> options_of(const CLI::App& command) {
  return command.get_options([&](const CLI::Option* o) { return o != command.get_help_ptr(); });
}

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return s;
}

bool repeatable(const CLI::Option* o) { return o->get_expected_max() > 1; }
bool takes_value(const CLI::Option* o) { return o->get_type_size_max() > 0 && !o->get_type_name().empty(); }

// CLI11's type name of an option's value, "INT:INT in [1 - 10000]": the
// type ("INT"), then what its validators accept ("INT in [1 - 10000]").
std::string value_type(const CLI::Option* o) { return o->get_type_name().substr(0, o->get_type_name().find(':')); }
std::string value_limits(const CLI::Option* o) {
  const std::string name = o->get_type_name();
  const auto colon = name.find(':');
  return colon == std::string::npos ? "" : name.substr(colon + 1);
}

// `--out TEXT`, `MANIFEST`: as the usage line and the table name it.
std::string label(const CLI::Option* o) {
  if (o->get_positional()) return upper(o->get_name());
  return o->get_name() + (takes_value(o) ? " " + value_type(o) : "");
}

std::string usage(const CLI::App& command, const std::string& words) {
  std::string line = "fibrodem " + words;
  for (const CLI::Option* o : options_of(command)) {
    if (o->get_positional()) continue;
    const std::string text = label(o);
    line += " " + (o->get_required() ? text : "[" + text + "]") + (repeatable(o) ? "..." : "");
  }
  for (const CLI::Option* o : options_of(command)) {
    if (!o->get_positional()) continue;
    const std::string text = label(o) + (repeatable(o) ? "..." : "");
    line += " " + (o->get_required() ? text : "[" + text + "]");
  }
  if (!subcommands_of(command).empty()) line += " [" + upper("subcommand") + " ...]";
  return line;
}

// A table cell: no line break, no unescaped '|'.
std::string cell(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : c == '\n' ? std::string(" ") : std::string(1, c);
  return out;
}

std::string options_table(const CLI::App& command) {
  std::ostringstream out;
  const auto options = options_of(command);
  if (options.empty()) return "";
  out << "| argument or option | what |\n|---|---|\n";
  for (const CLI::Option* o : options) {
    std::string what = o->get_description();
    if (!value_limits(o).empty()) what += "; " + value_limits(o);
    if (o->get_required()) what += "; required";
    if (repeatable(o) && !o->get_positional() && what.find("repeatable") == std::string::npos) what += " (repeatable)";
    out << "| `" << label(o) << "` | " << cell(what) << " |\n";
  }
  return out.str() + "\n";
}

CommandProse prose_of(const std::string& words, std::set<std::string>& used) {
  used.insert(words);
  const auto found = command_prose().find(words);
  return found == command_prose().end() ? CommandProse{} : found->second;
}

void section(std::ostringstream& out, const CLI::App& command, const std::string& words, const std::string& heading,
             std::set<std::string>& used) {
  const CommandProse prose = prose_of(words, used);
  out << heading << " " << words << "\n\n" << command.get_description() << ".\n\n```\n" << usage(command, words) << "\n";
  for (const std::string& line : prose.more_usage) out << line << "\n";
  out << "```\n\n";
  if (!prose.before.empty()) out << prose.before << "\n\n";
  out << options_table(command);
  if (!prose.after.empty()) out << prose.after << "\n\n";
  for (const CLI::App* sub : subcommands_of(command)) section(out, *sub, words + " " + sub->get_name(), heading + "#", used);
}

}  // namespace

std::string command_line_markdown(const CLI::App& app) {
  std::ostringstream out;
  std::set<std::string> used;
  const CommandProse page = prose_of("", used);
  out << "# Command line\n\n" << page.before << "\n\n| command | what |\n|---|---|\n";
  for (const CLI::App* sub : subcommands_of(app))
    out << "| [`" << sub->get_name() << "`](#" << sub->get_name() << ") | " << cell(sub->get_description()) << " |\n";
  out << "\n";
  for (const CLI::App* sub : subcommands_of(app)) section(out, *sub, sub->get_name(), "##", used);
  out << page.after << "\n";
  for (const auto& [words, prose] : command_prose())
    if (!used.count(words)) throw std::logic_error("apps/command_prose.cpp: prose for '" + words + "', which is no command");
  return out.str();
}

}  // namespace fibrodem::cli
