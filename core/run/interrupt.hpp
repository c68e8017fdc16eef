// Ending a run early on SIGINT or SIGTERM: the handler only records the
// signal; the simulation sees it at the end of the step in progress and stops
// there with every output flushed, status "interrupted".
#pragma once

#include <csignal>
#include <stdexcept>
#include <string>

namespace fibrodem {

// Installs handlers for SIGINT and SIGTERM that record the signal (the command
// line does; a library user may keep its own).
void install_interrupt_handlers();
// While it lives, `signal` (SIGINT or SIGTERM) is recorded as above instead of
// going to the handler that was installed (the Python module's run: a Ctrl-C
// stops the simulation at the end of a step rather than waiting for it to
// return to the interpreter); the earlier handler is put back after. It clears
// the recorded signal on the way in. Install from the main thread only.
class ScopedInterruptHandler {
 public:
  explicit ScopedInterruptHandler(int signal);
  ~ScopedInterruptHandler();
  ScopedInterruptHandler(const ScopedInterruptHandler&) = delete;
  ScopedInterruptHandler& operator=(const ScopedInterruptHandler&) = delete;

 private:
  int signal_;
  struct sigaction previous_ {};
};

// The signal received since the last clear (0: none).
int interrupt_signal();
// As if `signal` had arrived (tests; 0 clears).
void request_interrupt(int signal);
// "SIGINT", "SIGTERM" or "signal N".
std::string signal_name(int signal);

// Thrown out of a run stopped by a signal, after its outputs are written;
// the command line exits with 128 + signal (130, 143).
class InterruptedError : public std::runtime_error {
 public:
  InterruptedError(int signal, const std::string& what) : std::runtime_error(what), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

}  // namespace fibrodem
