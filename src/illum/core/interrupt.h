// Ctrl-C: the first SIGINT sets a flag that long-running loops poll so they stop cleanly
// (no output is written); a second SIGINT ends the process at once.
#pragma once

namespace illum {

void install_interrupt_handler();
bool interrupt_requested();
void request_interrupt();  // for tests and programmatic cancellation
void clear_interrupt();

// Thrown by a job that stopped because of an interrupt; the CLI exits 130 on it.
struct Interrupted {};

}  // namespace illum
