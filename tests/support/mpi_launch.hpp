// Helpers of the tests that start fibrodem under mpirun: whether mpirun is
// there, its command line, and `fibrodem run` of a scene file under it.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <string>

namespace fibrodem::testing {

inline bool have_mpirun() { return std::system("command -v mpirun > /dev/null 2>&1") == 0; }

// (CI runs as root, which OpenMPI refuses unless told; its own allocations
// that it never frees are not ours to report under AddressSanitizer.)
inline std::string mpirun(int ranks) {
  return "ASAN_OPTIONS=detect_leaks=0 OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -n " +
         std::to_string(ranks) + " --oversubscribe ";
}

// `fibrodem ARGS` under the launcher ("" for none), its output into `log`;
// the exit status (128 + the signal if one ended it).
inline int run_fibrodem(const std::string& launcher, const std::string& args, const std::filesystem::path& log) {
  const std::string command =
      launcher + std::string(FIBRODEM_BINARY_DIR) + "/fibrodem " + args + " > " + log.string() + " 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

// `fibrodem run SCENE --out OUT --quiet --no-report` under the launcher,
// its output into OUT.txt.
inline int run_scene(const std::string& launcher, const std::filesystem::path& scene,
                     const std::filesystem::path& out) {
  return run_fibrodem(launcher, "run " + scene.string() + " --out " + out.string() + " --quiet --no-report",
                      out.string() + ".txt");
}

}  // namespace fibrodem::testing
