#include "integrate/solver_spec.hpp"

#include <limits>
#include <vector>

#include "integrate/integrator.hpp"

namespace fibrodem {

namespace {
constexpr double kInf = std::numeric_limits<double>::infinity();
}

SolverSpec read_solver_spec(JsonReader r) {
  SolverSpec s;
  std::vector<std::string> methods = {"auto"};
  for (const auto& entry : integrators()) methods.push_back(entry.name);
  s.method = r.text("method", s.method, methods);
  // auto chooses the step or the tolerances itself: a manifest gives one or the other.
  for (const char* key : {"dt_ms", "rtol", "atol"}) {
    if (s.method == "auto" && r.has(key))
      throw ManifestError(r.path_of(key), std::string("solver.method \"auto\" chooses ") + key +
                                              " itself (set solver.accuracy, or name a method; on the command "
                                              "line, replace the whole solver: --set 'solver={\"method\":\"auto\"}')");
  }
  if (s.method != "auto" && r.has("accuracy"))
    throw ManifestError(r.path_of("accuracy"), "applies to solver.method \"auto\" only (got \"" + s.method + "\")");
  s.accuracy_ms = r.number("accuracy", s.accuracy_ms, 1e-4, 100.0);
  s.dt_ms = r.number("dt_ms", s.dt_ms, 1e-7, 10.0);
  if (s.method == "adaptive") {
    s.rtol = SolverSpec::kAdaptiveRtol;
    s.atol = SolverSpec::kAdaptiveAtol;
  }
  s.rtol = r.number("rtol", s.rtol, 1e-14, 1e-1);
  s.atol = r.number("atol", s.atol, 1e-16, 1.0);
  s.max_step_ms = r.number("max_step_ms", 0.0, 0.0, kInf);
  s.linear_solver = r.text("linear_solver", s.linear_solver, {"auto", "dense", "band", "krylov"});
  if (r.has("threads") && r.raw("threads").is_string())
    r.text("threads", "auto", {"auto"});  // "auto" is the default; anything else is an error
  else
    s.threads = static_cast<int>(r.integer("threads", s.threads, 0, 1024));
  s.partition = r.text("partition", "rcb", {"rcb", "scotch"}) == "scotch" ? PartitionMethod::scotch : PartitionMethod::rcb;
  if (r.has("lookup_tables")) s.lookup_tables = r.boolean("lookup_tables", false);
  s.simd = r.boolean("simd", s.simd);
  r.finish();
  return s;
}

}  // namespace fibrodem
