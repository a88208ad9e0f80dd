// rockwatch-monitor-liblcm: rockwatch-monitor with liblcm's receive thread behind --receive-path liblcm
// (lcm_input_source.hpp), for bench_monitor_latency's side-by-side runs only. Everything else is the monitor's own
// code (host_tools/monitor), so the two paths are measured through the same loop.
#include <exception>
#include <iostream>
#include <memory>

#include "lcm_input_source.hpp"
#include "monitor_run.hpp"

namespace monitor = rockwatch::monitor;

int main(int argc, char** argv) {
  const monitor::LiblcmInputFactory liblcm = [](lcm::LCM& lcm) -> std::unique_ptr<monitor::LiveInput> {
    return std::make_unique<rockwatch::bench::LcmInputSource>(lcm);
  };
  try {
    return monitor::run_monitor(argc, argv, std::cout, std::cerr, &liblcm);
  } catch (const std::exception& e) {
    std::cerr << "rockwatch-monitor-liblcm: internal error: " << e.what() << '\n';
    return monitor::kExitRuntime;
  }
}
