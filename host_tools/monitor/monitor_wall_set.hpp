// The walls one monitor follows, set up for its loop: the wall of the top-level settings, or those of the `walls`
// key (monitor_walls.hpp), each with its engines and its alarm printer, started on the engine --arith selects.
#pragma once

#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "monitor_config.hpp"
#include "monitor_output.hpp"
#include "rockwatch/firmware/multi_wall_monitor.hpp"
#include "rockwatch/firmware/wall_engine.hpp"
#include "rockwatch/sim/double_wall_engine.hpp"

namespace rockwatch::monitor {

// The engines the monitor can run: the loop is handed the one --arith selects.
struct MonitorEngines {
  firmware::WallEngine fixed;
  sim::DoubleWallEngine dbl;
  firmware::SampleEngine& selected(firmware::MonitorArithmetic a) {
    if (a == firmware::MonitorArithmetic::double_precision) return dbl;
    return fixed;
  }
};

// Each wall's name (printed by its alarm printer when there are several), settings, engines and printer.
struct MonitorWalls {
  std::vector<std::string> names;  // empty with the single top-level wall
  std::vector<firmware::MonitorSettings> settings;
  std::vector<std::unique_ptr<MonitorEngines>> engines;
  std::vector<std::unique_ptr<AlarmPrinter>> printers;
  std::unique_ptr<firmware::MultiWallMonitor> monitor = std::make_unique<firmware::MultiWallMonitor>();
  bool many() const { return !names.empty(); }
  firmware::MultiWallMonitor* operator->() { return monitor.get(); }
};

// Starts the walls' loops on the selected engines; on refusal prints a message naming the wall and the settings at
// fault and returns false. `out`: where the alarm printers write.
bool init_loop(MonitorWalls& walls, const MonitorConfig& config, firmware::Transport& transport, std::ostream& out,
               std::ostream& err);

}  // namespace rockwatch::monitor
