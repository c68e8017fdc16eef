#include "apps/openmp_spinning.hpp"

#include <unistd.h>

#include <cstdlib>
#include <cstring>

namespace fibrodem::cli {

namespace {
char** kept_argv = nullptr;
}

void keep_arguments(char** argv) { kept_argv = argv; }

void bound_openmp_spinning() {
  if (kept_argv == nullptr) return;
  if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr) return;
  // Under valgrind /proc/self/exe is valgrind's tool, not fibrodem: leave it be.
  if (const char* preload = std::getenv("LD_PRELOAD"); preload && std::strstr(preload, "vgpreload")) return;
  setenv("GOMP_SPINCOUNT", "10000", 1);
  execv("/proc/self/exe", kept_argv);  // returns only on failure: then run as we are
}

bool may_use_thread_team(const Scene& scene, const json& manifest) {
  if (scene.solver.threads == 1) return false;
  const bool one_cell = manifest.contains("tissue") && manifest["tissue"].is_object() &&
                        manifest["tissue"].value("builder", std::string()) == "single_cell";
  return !(one_cell && scene.solver.threads < 0);
}

}  // namespace fibrodem::cli
