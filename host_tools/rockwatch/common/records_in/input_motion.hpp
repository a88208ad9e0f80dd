// The ground motion as the analysis runs it: the horizontal record, the vertical one (a third column or a second
// file put on the horizontal time grid), both scaled by one factor when --scale-pga asks for a PGA.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "common/records_in/record_selection.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/records/record.hpp"
#include "rockwatch/sim/analysis.hpp"

namespace rockwatch::cli {

// What the reports say about a file; the samples themselves live in the GroundMotion.
struct RecordInfo {
  std::string path;
  std::string source;       // where in the file or suite: "suite npr9998-2015 set 3 component X", "channel HNE", or empty
  std::string format;       // "peer-at2" | "plain" | the other readers' ids
  std::string description;  // header text, may be empty
  std::string units;        // units the values were converted from
  double dt_s = 0.0;
  double t0_s = 0.0;
  std::size_t samples = 0;
  double peak_as_read_mps2 = 0.0;  // before --scale-pga
};

// The RecordInfo of a record read from a file, with `values` (one of its components, in m/s2) as the samples.
RecordInfo record_info(const records::Record& record, const std::vector<double>& values);

struct InputMotion {
  sim::GroundMotion motion;            // as run: aligned and scaled
  RecordInfo horizontal;
  std::optional<RecordInfo> vertical;  // set when the vertical comes from a file of its own (--vertical) or the suite
  bool vertical_from_third_column = false;
  double scale_factor = 1.0;           // applied to both components
  std::vector<std::string> notes;      // readers' notes and ours, for stderr
};

// The samples of `vertical` (one component) at the times of `horizontal`'s grid: put on one clock by the files'
// absolute start times when both state them, resampled by linear interpolation (bit for bit on the same grid), zero
// where the vertical has no samples. What that involved (another clock, another grid, a shorter span) is added to
// `notes`, naming vertical.path.
std::vector<double> vertical_on_horizontal_grid(const records::Record& horizontal, const records::Record& vertical,
                                                std::vector<std::string>& notes);

// What the input is made from: the files (the record options of simulate, replay, demo), the PGA to scale to, g.
struct InputRequest {
  RecordSelection record;
  std::optional<double> scale_pga_g;  // peak |ü| = G·g
  double g_mps2 = core::WallParameters{}.g_mps2;  // the wall's g: converts --scale-pga; G = g + v'' for lift-off
};

// Reads the files and prepares the input. Throws records::RecordError for file defects and UsageError for
// combinations the analysis cannot take (ambiguous vertical, a record with zero peak to scale, lift-off).
InputMotion prepare_input(const InputRequest& request);

}  // namespace rockwatch::cli
