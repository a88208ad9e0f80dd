// One monitor, many walls: the `walls` key of the configuration file. Each entry is one wall of the building:
//   {"name": "north",                      required: letters, digits, '_', '-', 1 to 24 characters, unique
//    "wall": {"b": 0.14, "h1": 1.6, ...},  optional: the fields of the top-level wall (or paper wall) to replace
//    "r": "exp" | "ana" | "impulse" | 0.8, optional: else the top-level r
//    "channels": {"accel": ..., "accel_batch": ..., "wall_sensor": ...}}   optional: its own inputs
// Every other setting (arithmetic, model, kappa, alarm, rate, observer, ...) is the top-level one. A wall publishes
// on the top-level output channels suffixed "_" + name (ROCKWATCH_WALL_STATE_north, ROCKWATCH_ALARM_north,
// ROCKWATCH_STATUS_north, ROCKWATCH_WALL_ESTIMATE_north), the wall named "wall" on them unsuffixed: a dashboard finds
// the walls by that suffix. Inputs: the top-level ground channels for all (one shared ground sensor) unless a wall
// names its own; its wall-sensor channel (with the observer) is the top-level one suffixed _NAME unless given.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "monitor_config.hpp"

namespace rockwatch::monitor {

// Fills config.walls from the `walls` value (label: "--config FILE: walls" for messages), after every top-level
// setting is final. Throws options::UsageError naming walls[i].KEY and what was expected.
void expand_monitor_walls(MonitorConfig& config, const nlohmann::json& walls, const std::string& label);

// The walls in the normalised settings (and so in the config digest).
nlohmann::json walls_json(const std::vector<WallMonitorConfig>& walls);

}  // namespace rockwatch::monitor
