#include "common/process/signal_interrupt.hpp"

#include <atomic>
#include <csignal>

namespace rockwatch::cli {

namespace {

// Lock-free atomics are the only shared state a signal handler may touch.
std::atomic<bool> g_cancel{false};
std::atomic<int> g_signal{0};
static_assert(std::atomic<bool>::is_always_lock_free && std::atomic<int>::is_always_lock_free,
              "the signal handler needs lock-free atomics");

extern "C" void on_stop_signal(int signal_number) {
  g_signal.store(signal_number);
  g_cancel.store(true);
  // The next signal of this kind ends the process the usual way: a user who presses Ctrl-C twice means it.
  struct sigaction default_action {};
  default_action.sa_handler = SIG_DFL;
  sigemptyset(&default_action.sa_mask);
  sigaction(signal_number, &default_action, nullptr);
}

}  // namespace

SignalInterrupt::SignalInterrupt() {
  g_cancel.store(false);
  g_signal.store(0);
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, &old_int_);
  sigaction(SIGTERM, &action, &old_term_);
}

SignalInterrupt::~SignalInterrupt() {
  sigaction(SIGINT, &old_int_, nullptr);
  sigaction(SIGTERM, &old_term_, nullptr);
}

const std::atomic<bool>* SignalInterrupt::flag() const { return &g_cancel; }

bool SignalInterrupt::interrupted() const { return g_cancel.load(); }

int SignalInterrupt::signal_number() const { return g_signal.load(); }

}  // namespace rockwatch::cli
