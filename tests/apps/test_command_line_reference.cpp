// docs/reference/command_line.md is what `fibrodem schema command-line`
// writes from the command line's declarations (apps/command_reference.cpp),
// as docs/reference/manifest.md is what the schema gives.
#include <doctest/doctest.h>

#include <string>

#include "support/scenes.hpp"

namespace {

fibrodem::testing::CommandOutput run_fibrodem(const std::string& arguments) {
  return fibrodem::testing::run_command(std::string(FIBRODEM_BINARY_DIR) + "/fibrodem " + arguments);
}

}  // namespace

TEST_CASE("docs/reference/command_line.md is what the command line declares") {
  const auto generated = run_fibrodem("schema command-line");
  REQUIRE(generated.status == 0);
  const std::string file = fibrodem::testing::read_file(std::filesystem::path(FIBRODEM_SOURCE_DIR) / "docs" /
                                                        "reference" / "command_line.md");
  CHECK_MESSAGE(generated.output == file,
                "docs/reference/command_line.md is not what the command line declares now: regenerate it with "
                "build/fibrodem schema command-line > docs/reference/command_line.md");
  // Every command has its section, whatever the first word asked for.
  for (const char* section : {"\n## run\n", "\n## vulnerable-window\n", "\n### bench headline\n", "\n## schema\n"})
    CHECK(generated.output.find(section) != std::string::npos);
}

TEST_CASE("the command line's reference is Markdown only") {
  const auto json = run_fibrodem("schema --json command-line 2>&1");
  CHECK(json.status == 2);
  CHECK(json.output.find("the command line has no JSON Schema") != std::string::npos);
}
