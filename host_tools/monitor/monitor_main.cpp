// rockwatch-monitor: the Linux LCM monitor. Everything is in monitor_run.cpp so the tests link the same code.
#include <exception>
#include <iostream>

#include "monitor_run.hpp"

int main(int argc, char** argv) {
  try {
    return rockwatch::monitor::run_monitor(argc, argv, std::cout, std::cerr);
  } catch (const std::exception& e) {
    std::cerr << "rockwatch-monitor: internal error: " << e.what() << '\n';
    return rockwatch::monitor::kExitRuntime;
  }
}
