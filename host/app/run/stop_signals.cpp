#include "app/run/stop_signals.h"

#include <csignal>

namespace wetdem::app {

namespace {

void (*volatile g_request)() = nullptr;

extern "C" void on_stop_signal(int s) {
  if (g_request) g_request();
  // A second Ctrl-C ends the process; a repeated SIGTERM only asks again (stop_signals.h).
  if (s == SIGINT) std::signal(SIGINT, SIG_DFL);
}

}  // namespace

void install_stop_signals(void (*request)()) {
  g_request = request;
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
}

}  // namespace wetdem::app
