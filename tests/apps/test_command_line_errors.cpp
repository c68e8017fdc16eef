// The command line's own errors (apps/fibrodem.cpp): a word that names no
// subcommand is named as such, with the nearest one, and the exit code
// says the arguments were not understood (docs/reference/exit_codes.md).
#include <doctest/doctest.h>

#include <string>

#include "support/scenes.hpp"

namespace {

using Outcome = fibrodem::testing::CommandOutput;

Outcome run_fibrodem(const std::string& arguments) {
  return fibrodem::testing::run_command(std::string(FIBRODEM_BINARY_DIR) + "/fibrodem " + arguments + " 2>&1");
}

}  // namespace

TEST_CASE("an unknown subcommand is named as unknown, with --help too, and the nearest one is offered") {
  for (const char* arguments : {"nonsense", "nonsense --help", "nonsense examples/default.json"}) {
    CAPTURE(arguments);
    const Outcome o = run_fibrodem(arguments);
    CAPTURE(o.output);
    CHECK(o.status == 109);  // CLI11's ExtrasError: arguments not expected
    CHECK(o.output.find("'nonsense' is not a subcommand") != std::string::npos);
    CHECK(o.output.find("vulnerable-window") != std::string::npos);  // the list of them
    CHECK(o.output.find("did you mean") == std::string::npos);      // nothing is near
  }
  const Outcome typo = run_fibrodem("valdiate x.json");
  CHECK(typo.status == 109);
  CHECK(typo.output.find("did you mean 'validate'?") != std::string::npos);
  // The general help still answers --help alone, and exits 0.
  const Outcome help = run_fibrodem("--help");
  CHECK(help.status == 0);
  CHECK(help.output.find("SUBCOMMAND") != std::string::npos);
}
