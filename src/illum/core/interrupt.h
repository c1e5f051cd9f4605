// Ctrl-C: the first SIGINT sets a flag that long-running loops poll so they stop cleanly
// (no output is written); a second SIGINT ends the process at once.
#pragma once

namespace illum {

void install_interrupt_handler();
// SIGTERM as well: how `mpirun` passes a Ctrl-C on to its ranks (then SIGKILL after a grace
// period), so a rank stops like an interrupted process instead of dying mid-write.
void install_termination_handler();
bool interrupt_requested();
// The signal that requested the interrupt (SIGINT, SIGTERM), 0 for request_interrupt().
int interrupt_signal();
void request_interrupt();  // for tests and programmatic cancellation
void clear_interrupt();

// Thrown by a job that stopped because of an interrupt; the CLI exits 130 on it.
struct Interrupted {};

}  // namespace illum
