#include "guarded_run.hpp"

#include <time.h>

#include <chrono>
#include <csignal>
#include <optional>

#include "binding.hpp"
#include "run/interrupt.hpp"

namespace py = pybind11;

namespace fibrodem::python {

namespace {
double thread_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}
}  // namespace

RunOutcome guarded_run(const Scene& scene, RunOptions options, bool catch_sigint) {
  RunOutcome outcome;
  std::exception_ptr set_up_error;
  {
    py::gil_scoped_release release;
    std::optional<ScopedInterruptHandler> sigint;
    if (catch_sigint) sigint.emplace(SIGINT);
    const auto set_up_start = std::chrono::steady_clock::now();
    try {
      std::lock_guard lock(registry_mutex());  // the registry loads plugins here
      outcome.simulation = std::make_unique<Simulation>(scene, shared_registry(), options);
    } catch (...) {
      set_up_error = std::current_exception();
    }
    outcome.set_up_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - set_up_start).count();
    if (outcome.simulation) {
      const auto start = std::chrono::steady_clock::now();
      const double cpu_start = thread_cpu_s();
      try {
        outcome.simulation->run();
      } catch (const InterruptedError& e) {
        outcome.status = "interrupted", outcome.message = e.what();
      } catch (const std::exception& e) {
        outcome.status = "failed", outcome.message = e.what();
      }
      outcome.run_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      outcome.run_cpu_s = thread_cpu_s() - cpu_start;
    }
  }
  if (set_up_error) std::rethrow_exception(set_up_error);
  return outcome;
}

std::function<void(double)> progress_callback(py::object callable, std::shared_ptr<std::exception_ptr> raised) {
  if (callable.is_none()) return {};
  // The callable is owned (and finally released) under the GIL only.
  auto owned = std::shared_ptr<py::object>(new py::object(std::move(callable)), [](py::object* o) {
    py::gil_scoped_acquire gil;
    delete o;
  });
  return [owned, raised](double t_ms) {
    py::gil_scoped_acquire gil;
    try {
      (*owned)(t_ms);
    } catch (...) {
      *raised = std::current_exception();
      throw std::runtime_error("the progress callback raised an exception");
    }
  };
}

}  // namespace fibrodem::python
