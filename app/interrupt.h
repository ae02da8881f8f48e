#pragma once
/// SIGINT and SIGTERM during a simulation: the handler only raises a flag (no exception, no
/// output), which the simulator reads between steps and between output rows; it then stops, the
/// rows computed so far are written whole, and the command exits with 128 + the signal number
/// (130 for SIGINT, 143 for SIGTERM). A second signal kills the process at once (the handler is
/// installed for one delivery).

#include <atomic>

namespace momenta {

/// Installs the handler for SIGINT and SIGTERM.
void InstallInterruptHandler();

/// Raised by the handler.
const std::atomic<bool>& InterruptRequested();

/// The signal that raised the flag (0 when none).
int InterruptSignal();

}  // namespace momenta
