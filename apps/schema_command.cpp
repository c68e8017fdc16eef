// `fibrodem schema`: the JSON Schemas embedded in the program, as they are
// (--json) or as the reference in docs/reference/ (--markdown); and the
// command line's reference, from its declarations.
#include <iostream>

#include "apps/command_reference.hpp"
#include "apps/commands.hpp"
#include "scene/schema/schema_markdown.hpp"

namespace fibrodem::cli {

int schema_command(const SchemaArgs& args, const CLI::App& app) {
  if (args.kind == "command-line") {
    if (args.format == "json") {
      print_failure("error", "--json: the command line has no JSON Schema; its reference is Markdown (--markdown)");
      return 2;
    }
    std::cout << command_line_markdown(app);
    return 0;
  }
  const SchemaKind kind = schema_kind_named(args.kind);
  if (args.format == "json") std::cout << schema_text(kind);
  else std::cout << schema_markdown(kind);
  return 0;
}

}  // namespace fibrodem::cli
