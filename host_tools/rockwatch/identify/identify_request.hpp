// What `rockwatch identify` was asked to do, parsed and validated from its command line.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "common/records_in/record_selection.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"

namespace rockwatch::cli {

struct IdentifyRequest {
  std::string wall_sensors_path;             // --wall-sensors: the test's transducer samples
  std::optional<RecordSelection> record;     // the ground motion of a forced test; none: a snap-back test
  std::optional<double> scale_pga_g;         // --scale-pga, as simulate
  core::WallParameters start_wall = core::paper_wall();  // the starting wall (simulate's wall options)
  std::string start_wall_text = "paper wall";
  core::Restitution start_r{};               // --r: the start of r (default exp)
  double max_step_s = 0.001;                 // --max-step
  bool json = false;
  std::optional<std::string> plot_path;      // --plot FILE.png
  std::optional<std::string> wall_out_path;  // --wall-out FILE.json
};

struct IdentifyParse {
  std::optional<IdentifyRequest> request;
  std::string help_text;
};

IdentifyParse parse_identify_arguments(int argc, const char* const* argv);

}  // namespace rockwatch::cli
