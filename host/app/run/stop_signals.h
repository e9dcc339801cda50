#pragma once
// How a run stops on a signal. SIGTERM is how a batch system (Slurm at a task's time limit), `timeout` and a
// study driver ask a run to stop: at the next step boundary, writing its checkpoint. Several can arrive for
// one stop: `timeout` and Slurm signal the whole process group, and `study run` forwards the signal to its
// run processes, so a run process gets two. Every SIGTERM therefore only asks again; the hard stop is SIGKILL
// (timeout -k, Slurm's KillWait). SIGINT keeps the interactive rule: the first Ctrl-C asks, the second one
// ends the process at once.
namespace wetdem::app {

// Installs the SIGINT and SIGTERM handlers; `request` (async-signal-safe) is called on each stop request.
void install_stop_signals(void (*request)());

}  // namespace wetdem::app
