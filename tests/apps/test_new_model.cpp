// `fibrodem new-model`: a skeleton whose name gives a class name that the
// skeleton also declares (its enums of indices: State, Param, Input,
// Output) still compiles; the class takes the kind's word after it.
#include <doctest/doctest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "support/scenes.hpp"

namespace fs = std::filesystem;

namespace {

int shell(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("new-model: a name that collides with the skeleton's own declarations still compiles") {
  const fs::path dir = fibrodem::testing::scratch_dir("new_model_names");
  const std::string fibrodem = std::string(FIBRODEM_BINARY_DIR) + "/fibrodem";
  struct Case {
    const char *kind, *name, *class_name;
  };
  const Case cases[] = {{"ionic", "state", "StateModel"},        {"ionic", "input", "InputModel"},
                        {"myofilament", "output", "OutputModel"}, {"myofilament", "param", "ParamModel"},
                        {"contact-law", "param", "ParamLaw"},     {"contact-law", "state", "StateLaw"},
                        {"ionic", "my_state", "MyState"}};
  for (const Case& c : cases) {
    const std::string kind = c.kind, name = c.name;
    CAPTURE(kind);
    CAPTURE(name);
    const fs::path folder = dir / (std::string(c.kind) + "_" + c.name);
    REQUIRE(shell(fibrodem + " new-model " + c.name + " --kind " + c.kind + " --dir '" + folder.string() +
                  "' > /dev/null") == 0);
    const std::string source = fibrodem::testing::read_file(folder / (std::string(c.name) + ".cpp"));
    CHECK(source.find(std::string("class ") + c.class_name + " final") != std::string::npos);
  }
  // One of each kind through the compiler, as a user's build would see it
  // (syntax and types: the SDK's headers, no link).
  for (const std::string folder : {"ionic_state", "myofilament_output", "contact-law_param"}) {
    CAPTURE(folder);
    const std::string name = folder.substr(folder.rfind('_') + 1);
    const std::string compile = std::string(FIBRODEM_CXX_COMPILER) + " -std=c++20 -fsyntax-only -I '" +
                                FIBRODEM_SOURCE_DIR + "/sdk' '" + (dir / folder / (name + ".cpp")).string() + "' 2> '" +
                                (dir / folder / "compile.txt").string() + "'";
    CHECK_MESSAGE(shell(compile) == 0, fibrodem::testing::read_file(dir / folder / "compile.txt"));
  }
}
