// `fibrodem schema`: the JSON Schemas embedded in the program, as they are
// (--json) or as the reference in docs/reference/ (--markdown).
#include <iostream>

#include "apps/commands.hpp"
#include "scene/schema/schema_markdown.hpp"

namespace fibrodem::cli {

int schema_command(const SchemaArgs& args) {
  const SchemaKind kind = schema_kind_named(args.kind);
  if (args.format == "json") std::cout << schema_text(kind);
  else std::cout << schema_markdown(kind);
  return 0;
}

}  // namespace fibrodem::cli
