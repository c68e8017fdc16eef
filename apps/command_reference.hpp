// The command line's reference page (docs/reference/command_line.md), which
// `fibrodem schema command-line` prints: generated from the commands'
// CLI11 declarations and the prose kept beside them (command_prose.cpp).
#pragma once

#include <map>
#include <string>
#include <vector>

namespace CLI {
class App;
}

namespace fibrodem::cli {

// What a command's section says besides its declarations.
struct CommandProse {
  std::vector<std::string> more_usage;  // usage lines after the declared one
  std::string before;                   // paragraphs before the table of options
  std::string after;                    // paragraphs after it (links to guides, outputs, exit codes)
};

// The prose of the commands that have some, by their words ("run", "bench
// headline"); "" names the page itself (before: its introduction, after: its
// closing sections).
const std::map<std::string, CommandProse>& command_prose();

// The whole page, from `app` with every command declared; std::logic_error
// if command_prose() names a command `app` does not declare.
std::string command_line_markdown(const CLI::App& app);

}  // namespace fibrodem::cli
