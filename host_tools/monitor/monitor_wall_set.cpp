#include "monitor_wall_set.hpp"

#include "monitor_run.hpp"
#include "rockwatch/options/option_values.hpp"

namespace rockwatch::monitor {

bool init_loop(MonitorWalls& walls, const MonitorConfig& config, firmware::Transport& transport, std::ostream& out,
               std::ostream& err) {
  if (config.walls.empty()) {
    walls.settings.push_back(config.settings);
  } else {
    for (const WallMonitorConfig& w : config.walls) {
      walls.names.push_back(w.name);
      walls.settings.push_back(w.settings);
    }
  }
  std::vector<firmware::SampleEngine*> engines;
  std::vector<firmware::MonitorListener*> listeners;
  for (std::size_t i = 0; i < walls.settings.size(); ++i) {
    walls.engines.push_back(std::make_unique<MonitorEngines>());
    walls.printers.push_back(std::make_unique<AlarmPrinter>(out, walls.many() ? walls.names[i] : std::string()));
    engines.push_back(&walls.engines.back()->selected(config.settings.arithmetic));
    listeners.push_back(walls.printers.back().get());
  }
  const firmware::MultiWallError me =
      walls->init(walls.settings.data(), engines.data(), listeners.data(), walls.settings.size(), transport);
  if (me == firmware::MultiWallError::ok) return true;
  const std::size_t at = walls->failed_wall();
  const std::string wall_name = walls.many() ? "walls[" + std::to_string(at) + "] (" + walls.names[at] + "): " : "";
  const std::string wall_origin = walls.many() ? config.walls[at].wall_origin : config.wall_origin;
  err << kMessagePrefix << "error: " << wall_name;
  if (me != firmware::MultiWallError::wall) {
    err << firmware::multi_wall_error_message(me) << '\n';
    return false;
  }
  const firmware::MonitorError e = walls->wall_error();
  if (e == firmware::MonitorError::engine) {
    const firmware::WallEngineError w = walls->wall(at).engine_error();
    if (w == firmware::WallEngineError::fixed_point_setup) {
      err << "the wall (" << wall_origin << ") at the sample rate " << options::number_text(config.settings.sample_rate_hz)
          << " Hz (" << config.rate_origin << ") is outside the fixed-point engine's formats: "
          << firmware::wall_engine_error_message(w);
    } else if (w == firmware::WallEngineError::indicator_constants) {
      err << "the wall (" << wall_origin << ") is outside the alarm's formats: "
          << firmware::wall_engine_error_message(w);
    } else {
      err << "the wall engine refused the settings: " << firmware::wall_engine_error_message(w);
    }
  } else {
    err << "the monitor loop refused the settings: " << firmware::monitor_error_message(e);
  }
  err << '\n';
  return false;
}

}  // namespace rockwatch::monitor
