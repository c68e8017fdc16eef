#include "run/interrupt.hpp"

#include <csignal>

namespace fibrodem {

namespace {
volatile std::sig_atomic_t received = 0;

extern "C" void record_signal(int signal) { received = signal; }


struct sigaction recording_action() {
  struct sigaction action {};
  action.sa_handler = record_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;  // a write in progress is not cut short
  return action;
}
}  // namespace

void install_interrupt_handlers() {
  const struct sigaction action = recording_action();
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

ScopedInterruptHandler::ScopedInterruptHandler(int signal) : signal_(signal) {
  received = 0;
  const struct sigaction action = recording_action();
  sigaction(signal_, &action, &previous_);
}

ScopedInterruptHandler::~ScopedInterruptHandler() { sigaction(signal_, &previous_, nullptr); }

int interrupt_signal() { return received; }

void request_interrupt(int signal) { received = signal; }

std::string signal_name(int signal) {
  switch (signal) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    default: return "signal " + std::to_string(signal);
  }
}

}  // namespace fibrodem
