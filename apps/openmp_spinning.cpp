#include "apps/openmp_spinning.hpp"

#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <strings.h>

namespace fibrodem::cli {

namespace {

char** kept_argv = nullptr;

// Whether the user binds OpenMP's threads to places (OMP_PLACES set, or
// OMP_PROC_BIND set other than false): libgomp then pins the first thread
// to one CPU as it loads, and a process started again from that thread
// would inherit that one CPU alone. (GOMP_CPU_AFFINITY names its CPUs, which
// a restart keeps.)
bool user_binds_openmp_threads() {
  if (std::getenv("OMP_PLACES") != nullptr) return true;
  const char* bind = std::getenv("OMP_PROC_BIND");
  return bind != nullptr && strcasecmp(bind, "false") != 0;
}

}  // namespace

void keep_arguments(char** argv) { kept_argv = argv; }

void bound_openmp_spinning() {
  if (kept_argv == nullptr) return;
  if (std::getenv("OMP_WAIT_POLICY") != nullptr || std::getenv("GOMP_SPINCOUNT") != nullptr) return;
  if (user_binds_openmp_threads()) return;
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
