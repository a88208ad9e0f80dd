#include "stop_signals.hpp"

namespace rockwatch::monitor {

namespace {

volatile std::sig_atomic_t g_stop_signal = 0;

extern "C" void on_stop_signal(int signal_number) { g_stop_signal = signal_number; }

}  // namespace

StopSignals::StopSignals() {
  g_stop_signal = 0;
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // no SA_RESTART: the signal interrupts the input's wait at once
  sigaction(SIGINT, &action, &old_int_);
  sigaction(SIGTERM, &action, &old_term_);
  // A reader of stdout that goes away must not kill the monitor: it keeps publishing on LCM.
  struct sigaction ignore {};
  ignore.sa_handler = SIG_IGN;
  sigemptyset(&ignore.sa_mask);
  sigaction(SIGPIPE, &ignore, &old_pipe_);
}

StopSignals::~StopSignals() {
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
  sigaction(SIGPIPE, &old_pipe_, nullptr);
}

bool StopSignals::stopped() { return g_stop_signal != 0; }

std::string StopSignals::stopped_by() {
  const int s = g_stop_signal;
  if (s == SIGINT) return "SIGINT";
  if (s == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(s);
}

}  // namespace rockwatch::monitor
