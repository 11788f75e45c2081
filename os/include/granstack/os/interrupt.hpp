#pragma once
// SIGINT, SIGTERM and SIGHUP as a request to stop: long work polls interrupt_signal() and ends
// cleanly (children stopped, cases marked interrupted). A second signal ends granstack at once;
// its children still die with it (os::start's parent-death signal).
namespace granstack::os {

// Installs the handlers (idempotent).
void install_interrupt_handlers();
// The first stop signal received, or 0.
int interrupt_signal();
// The exit code for a stop by `signal`: 128 + signal (130 for SIGINT, 143 for SIGTERM).
inline int exit_code_for_signal(int signal) { return 128 + signal; }

}  // namespace granstack::os
