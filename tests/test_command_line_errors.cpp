// The command line's own errors (apps/fibrodem.cpp): a word that names no
// subcommand is named as such, with the nearest one, and the exit code
// says the arguments were not understood (docs/reference/exit_codes.md).
#include <doctest/doctest.h>

#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace {

struct Outcome {
  int status;
  std::string output;  // stdout and stderr
};

Outcome fibrodem(const std::string& arguments) {
  const std::string command = std::string(FIBRODEM_BINARY_DIR) + "/fibrodem " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  REQUIRE(pipe != nullptr);
  std::string output;
  char buffer[512];
  while (fgets(buffer, sizeof buffer, pipe)) output += buffer;
  const int status = pclose(pipe);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

}  // namespace

TEST_CASE("an unknown subcommand is named as unknown, with --help too, and the nearest one is offered") {
  for (const char* arguments : {"nonsense", "nonsense --help", "nonsense examples/default.json"}) {
    CAPTURE(arguments);
    const Outcome o = fibrodem(arguments);
    CAPTURE(o.output);
    CHECK(o.status == 109);  // CLI11's ExtrasError: arguments not expected
    CHECK(o.output.find("'nonsense' is not a subcommand") != std::string::npos);
    CHECK(o.output.find("vulnerable-window") != std::string::npos);  // the list of them
    CHECK(o.output.find("did you mean") == std::string::npos);      // nothing is near
  }
  const Outcome typo = fibrodem("valdiate x.json");
  CHECK(typo.status == 109);
  CHECK(typo.output.find("did you mean 'validate'?") != std::string::npos);
  // The general help still answers --help alone, and exits 0.
  const Outcome help = fibrodem("--help");
  CHECK(help.status == 0);
  CHECK(help.output.find("SUBCOMMAND") != std::string::npos);
}
