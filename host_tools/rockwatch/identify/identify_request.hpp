// What `rockwatch identify` was asked to do, parsed and validated from its command line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "common/records_in/record_selection.hpp"
#include "rockwatch/core/restitution.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/options/wall_options.hpp"
#include "rockwatch/sim/identification.hpp"

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
  int bootstrap = 0;                         // --bootstrap N: parametric bootstrap replicates (0: none)
  std::uint64_t bootstrap_seed = 1;          // --bootstrap-seed
  std::size_t jobs = 0;                      // --jobs: the bootstrap's threads (0: every hardware thread)
};

struct IdentifyParse {
  std::optional<IdentifyRequest> request;
  std::string help_text;
};

// What `rockwatch identify` identifies with, as typed values (an empty optional: not given). The command line's
// parser converts its texts into them, the Python module (rockwatch.identify) fills them from its keywords; both
// call build_identify_request, so the checks and the messages (naming the option) are the same.
struct IdentifySettings {
  std::optional<std::string> wall_sensors;           // --wall-sensors FILE.csv: required
  RecordSelectionSettings record;                    // neither --record nor --suite: a snap-back test
  std::optional<double> scale_pga_g;                 // --scale-pga [g]
  options::WallChoice wall;                          // the starting wall, checked (check_wall_settings)
  std::optional<options::RestitutionSetting> r;      // --r: the start of r; none: the wall file's, else exp
  std::optional<double> max_step_s;                  // --max-step [s]
  bool json = false;                                 // --json
  std::optional<std::string> plot, wall_out;         // --plot FILE.png, --wall-out FILE.json
  std::optional<long long> bootstrap, jobs;          // --bootstrap N, --jobs N
  std::optional<std::uint64_t> bootstrap_seed;       // --bootstrap-seed S
};

// Checks the settings and builds the request. Throws UsageError naming the option at fault.
IdentifyRequest build_identify_request(const IdentifySettings& settings);

// Parses `rockwatch identify` arguments (argv[0] is the command name) into IdentifySettings, then
// build_identify_request.
IdentifyParse parse_identify_arguments(int argc, const char* const* argv);

// The identification's settings from the request (the starting wall and r, the step, the bootstrap); the caller adds
// the samples and the ground motion (the command and the Python module alike).
sim::IdentificationInput identification_input(const IdentifyRequest& request);

}  // namespace rockwatch::cli
