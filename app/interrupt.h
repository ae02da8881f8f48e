#pragma once
/// SIGINT and SIGTERM during a simulation: the handler only raises a flag (no exception, no
/// output), which the simulator reads between steps and between output rows; it then stops, the
/// rows computed so far are written whole, and the command exits with 128 + the signal number
/// (130 for SIGINT, 143 for SIGTERM). A second signal kills the process at once (the handler is
/// installed for one delivery). The native-code compilation that may precede a run reads the same
/// flag (NativeCodeOptions::interrupt): it stops its compilers and removes their files.

#include <signal.h>

#include <atomic>

namespace momenta {

/// Installs the handler for SIGINT and SIGTERM.
void InstallInterruptHandler();

/// Raised by the handler.
const std::atomic<bool>& InterruptRequested();

/// The signal that raised the flag (0 when none).
int InterruptSignal();

/// "SIGINT", "SIGTERM" (or "signal N").
const char* InterruptSignalName(int signal_number);

/// The handler for one stage (the native-code compilation): installed on construction, the
/// previous actions back on destruction unless a signal came (the command then stops).
class ScopedInterruptHandler {
 public:
  ScopedInterruptHandler();
  ~ScopedInterruptHandler();
  ScopedInterruptHandler(const ScopedInterruptHandler&) = delete;
  ScopedInterruptHandler& operator=(const ScopedInterruptHandler&) = delete;

 private:
  struct sigaction previous_int_ {}, previous_term_ {};
};

}  // namespace momenta
