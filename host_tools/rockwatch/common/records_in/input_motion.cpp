#include "common/records_in/input_motion.hpp"

#include <cmath>
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "common/records_in/align.hpp"
#include "common/records_in/record_selection.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/records/record.hpp"

namespace rockwatch::cli {

namespace {

void take_notes(std::vector<std::string>& notes, const records::Record& r) {
  notes.insert(notes.end(), r.notes.begin(), r.notes.end());
}

// The vertical of --vertical, or the Z component of the same suite set (--vertical-from-suite): the same grid, so the
// resampling below copies it bit for bit and has nothing to note.
std::vector<double> vertical_from_file(const InputRequest& q, const records::Record& horizontal, InputMotion& in) {
  const RecordSelection& s = q.record;
  const std::string& path = *s.vertical_path;
  records::Record v = records::read_record(path, s.vertical_read_options());
  take_notes(in.notes, v);
  if (!v.vertical_mps2.empty()) {
    throw UsageError(vertical_source_text(s) +
                     " has three columns (time, horizontal, vertical): expected one acceleration component; extract "
                     "the vertical column, or pass the file as --record alone");
  }
  in.vertical = record_info(v, v.horizontal_mps2);
  if (s.vertical_from_suite) {
    in.vertical->source = suite_record_text(*s.suite, 'Z');
  } else if (s.vertical_channel) {
    in.vertical->source = "channel " + *s.vertical_channel;
  }
  return vertical_on_horizontal_grid(horizontal, v, in.notes);
}

void scale_to_pga(const InputRequest& q, InputMotion& in) {
  const double peak = in.horizontal.peak_as_read_mps2;
  if (!(peak > 0.0)) {
    throw UsageError("--scale-pga: the horizontal record " + q.record.record_path +
                     " has peak |u''| = 0, so no factor can scale it to " + number_text(*q.scale_pga_g) + " g");
  }
  in.scale_factor = *q.scale_pga_g * q.g_mps2 / peak;
  for (double& u : in.motion.ug_mps2) u *= in.scale_factor;
  for (double& v : in.motion.vg_mps2) v *= in.scale_factor;
}

// G = g + v'' <= 0 means the wall leaves the ground: outside the model (SPEC §1). Checked here, after scaling, to
// name the file and the time; the analysis would also refuse it, by sample index.
void check_no_lift_off(const InputRequest& q, const InputMotion& in) {
  const std::vector<double>& v = in.motion.vg_mps2;
  for (std::size_t k = 0; k < v.size(); ++k) {
    const double big_g = q.g_mps2 + v[k];
    if (big_g > 0.0) continue;
    const std::string source = in.vertical_from_third_column ? "the third column of " + q.record.record_path
                                                             : vertical_source_text(q.record);
    std::string message = source + ": v'' = " + number_text(v[k]) + " m/s2 at t = " +
                           number_text(static_cast<double>(k) * in.motion.dt_s) + " s";
    if (in.scale_factor != 1.0) message += " (after --scale-pga, factor " + number_text(in.scale_factor) + ")";
    message += " gives G = g + v'' = " + number_text(big_g) +
               " m/s2 <= 0: the wall lifts off the ground, which is outside the model";
    throw UsageError(message);
  }
}

}  // namespace

std::vector<double> vertical_on_horizontal_grid(const records::Record& horizontal, const records::Record& vertical,
                                                std::vector<std::string>& notes) {
  // Files that state an absolute start (miniSEED, ESM) are put on one clock: two channels of one station start a
  // fraction of a second apart, and their own times both begin at 0.
  double offset_s = 0.0;
  if (vertical.start_time_ns && horizontal.start_time_ns) {
    offset_s = static_cast<double>(*vertical.start_time_ns - *horizontal.start_time_ns) * 1e-9;
    if (offset_s != 0.0) {
      notes.push_back("vertical record " + vertical.path + " starts " + number_text(std::fabs(offset_s)) + " s " +
                         (offset_s > 0.0 ? "after" : "before") +
                      " the horizontal by the files' start times: aligned on that clock");
    }
  }
  const TimeGrid source{vertical.t0_s + offset_s, vertical.dt_s, vertical.horizontal_mps2.size()};
  const TimeGrid target{horizontal.t0_s, horizontal.dt_s, horizontal.horizontal_mps2.size()};
  if (source.dt_s != target.dt_s || source.t0_s != target.t0_s) {
    notes.push_back("vertical record " + vertical.path + " (dt " + number_text(source.dt_s) + " s, t0 " +
                    number_text(source.t0_s) + " s) resampled by linear interpolation onto the horizontal grid (dt " +
                    number_text(target.dt_s) + " s, t0 " + number_text(target.t0_s) + " s)");
  }
  const double v_end_s = source.t0_s + source.dt_s * (static_cast<double>(source.count) - 1.0);
  const double h_end_s = target.t0_s + target.dt_s * (static_cast<double>(target.count) - 1.0);
  if (source.t0_s > target.t0_s || v_end_s < h_end_s) {
    notes.push_back("vertical record " + vertical.path + " spans t = " + number_text(source.t0_s) + " to " +
                    number_text(v_end_s) + " s, the horizontal " + number_text(target.t0_s) + " to " +
                    number_text(h_end_s) + " s: v'' = 0 where it has no samples");
  }
  return resample_linear(vertical.horizontal_mps2, source, target);
}

RecordInfo record_info(const records::Record& r, const std::vector<double>& values) {
  RecordInfo info;
  info.path = r.path;
  info.format = r.format;
  info.description = r.description;
  info.units = std::string(records::accel_unit_name(r.units_in_file));
  info.dt_s = r.dt_s;
  info.t0_s = r.t0_s;
  info.samples = values.size();
  info.peak_as_read_mps2 = sim::peak_abs(values);
  return info;
}

InputMotion prepare_input(const InputRequest& q) {
  InputMotion in;
  const RecordSelection& s = q.record;
  records::Record h = records::read_record(s.record_path, s.read_options);
  take_notes(in.notes, h);
  in.horizontal = record_info(h, h.horizontal_mps2);
  in.horizontal.source = selection_text(s);

  if (!h.vertical_mps2.empty()) {
    if (s.vertical_path) {
      throw UsageError("ambiguous vertical input: " + s.record_path + " has a third (vertical) column and " +
                       vertical_source_text(s) + " was given too; drop the vertical option or remove the column");
    }
    in.vertical_from_third_column = true;
    in.motion.vg_mps2 = std::move(h.vertical_mps2);
  } else if (s.vertical_path) {
    in.motion.vg_mps2 = vertical_from_file(q, h, in);
  }
  in.motion.dt_s = h.dt_s;
  in.motion.ug_mps2 = std::move(h.horizontal_mps2);

  if (q.scale_pga_g) scale_to_pga(q, in);
  check_no_lift_off(q, in);
  return in;
}

}  // namespace rockwatch::cli
