#pragma once
// Ctrl-C (SIGINT) and a supervisor's SIGTERM during `esdslam run`: the first one asks the run
// loop to stop after the current frame (its stop predicate reads StopSignal()), so that every
// output is still written; a second one exits at once (status 128 + signal) with what is on disk
// (the live outputs are flushed per frame, system/live_outputs.h). The library knows nothing
// of signals: only this flag crosses into it, through the run loop's stop predicate.

namespace esdslam::cli {

// Installs the handler for SIGINT and SIGTERM (once per process; later calls do nothing).
void InstallStopSignals();
// 0 while no stop signal came, else the first one's number (SIGINT, SIGTERM).
int StopSignal();
// Blocks (a read on a self-pipe the handler writes to, no polling) until the first stop signal
// (at once if one came already); installs the handler if needed. Returns its number.
int WaitForStopSignal();

}  // namespace esdslam::cli
