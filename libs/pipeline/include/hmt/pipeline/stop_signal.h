// SIGINT and SIGTERM as a request to stop between two scans: the first one
// sets a flag the job polls after each scan (it then writes a checkpoint and
// stops with ExitCode::kInterrupted); the handler steps aside as it fires,
// so a second signal ends the process at once, as users expect of Ctrl-C.
#pragma once

namespace hmt::pipeline {

void install_stop_handlers();
// 0, or the signal received since install_stop_handlers().
int stop_signal();
// "SIGINT", "SIGTERM" or "signal N".
const char* signal_name(int sig);

}  // namespace hmt::pipeline
