// `import rockwatch`: the engine of the `rockwatch` tool for Python (docs/python.md).
//
// Nothing here computes but simulate's scaling to a PGA (the one line of the tool's input preparation, repeated: the
// tool scales as it reads files, the module's simulate takes samples). Every function fills the typed settings the
// command's parser fills from its texts (WallSettings, RecordSelectionSettings, SimulateSettings, StaticSettings,
// IdentifySettings) and checks them with the same function (check_wall_settings, check_record_selection,
// apply_simulate_settings, build_static_request, build_identify_request), so the validation and the messages are the
// tool's, naming the option the keyword stands for; no argument text is made. Then it calls what the command calls
// (records::read_record through prepare_input, sim::analyse, sim::response_spectrum and the intensity measures,
// core::run_static_check, sim::identify) and returns what the command's --json prints, with the same keys
// (simulate's result_json itself). Errors the tool reports as "rockwatch COMMAND: error: MESSAGE" (exit 2) are
// ValueError(MESSAGE) here. The GIL is released while the engine runs.
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "common/records_in/input_motion.hpp"
#include "common/process/output_file.hpp"
#include "common/records_in/record_selection.hpp"
#include "common/records_in/wall_sensors.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/options/alarm_options.hpp"
#include "rockwatch/options/engine_options.hpp"
#include "rockwatch/options/observer_options.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "rockwatch/options/wall_file.hpp"
#include "rockwatch/options/wall_options.hpp"
#include "rockwatch/records/record_error.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "identify/identify_report.hpp"
#include "identify/identify_request.hpp"
#include "rockwatch/core/static_check.hpp"
#include "rockwatch/core/stepper_alarm_chain.hpp"
#include "rockwatch/sim/identification.hpp"
#include "rockwatch/sim/intensity_measures.hpp"
#include "rockwatch/sim/measure_error.hpp"
#include "rockwatch/sim/response_spectrum.hpp"
#include "simulate/simulate_report.hpp"
#include "simulate/simulate_request.hpp"
#include "simulate/simulate_settings.hpp"
#include "spectrum/spectrum_request.hpp"
#include "static/static_report.hpp"
#include "static/static_request.hpp"
#include "study_module.hpp"

namespace py = pybind11;

namespace rockwatch::python {

namespace {

using Json = nlohmann::ordered_json;
using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;

// A double as text that converts back to the same double (Wall's repr).
std::string repr_number(double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

py::object to_python(const Json& j) {
  switch (j.type()) {
    case Json::value_t::null: return py::none();
    case Json::value_t::boolean: return py::bool_(j.get<bool>());
    case Json::value_t::number_integer: return py::int_(j.get<std::int64_t>());
    case Json::value_t::number_unsigned: return py::int_(j.get<std::uint64_t>());
    case Json::value_t::number_float: return py::float_(j.get<double>());
    case Json::value_t::string: return py::str(j.get<std::string>());
    case Json::value_t::array: {
      py::list list;
      for (const Json& item : j) list.append(to_python(item));
      return std::move(list);
    }
    case Json::value_t::object: {
      py::dict dict;
      for (auto it = j.begin(); it != j.end(); ++it) dict[py::str(it.key())] = to_python(it.value());
      return std::move(dict);
    }
    default: return py::none();
  }
}

py::array_t<double> numpy_copy(const std::vector<double>& values) {
  py::array_t<double> a(static_cast<py::ssize_t>(values.size()));
  double* out = a.mutable_data();
  for (std::size_t i = 0; i < values.size(); ++i) out[i] = values[i];
  return a;
}

std::vector<double> vector_of(const Array& a, const char* name) {
  if (a.ndim() != 1) {
    throw options::UsageError(std::string(name) + " must be a one-dimensional array of samples (got " +
                              std::to_string(a.ndim()) + " dimensions)");
  }
  const double* p = a.data();
  return std::vector<double>(p, p + a.shape(0));
}

// ---------------------------------------------------------------------------------------------------------- records

struct Record {
  double dt_s = 0.0;
  py::array_t<double> accel_mps2;
  py::object vertical_mps2 = py::none();
  std::string path, format, units, description, source;
  double t0_s = 0.0;
  std::vector<std::string> notes;
};

Record read_record(const std::string& path, const std::optional<std::string>& units, const std::optional<double>& dt_s,
                   const std::optional<double>& gain_counts_per_mps2, const std::optional<std::string>& channel,
                   const std::optional<std::string>& component, const std::optional<std::string>& vertical,
                   const std::optional<std::string>& vertical_channel, double g_mps2) {
  cli::RecordSelectionSettings s;  // simulate's record options
  s.record = path;
  s.units = units;
  s.dt_s = dt_s;
  s.gain_counts_per_mps2 = gain_counts_per_mps2;
  s.channel = channel;
  s.component = component;
  s.vertical = vertical;
  s.vertical_channel = vertical_channel;
  const cli::InputRequest request{cli::check_record_selection(s, g_mps2), std::nullopt, g_mps2};
  cli::InputMotion in;
  {
    py::gil_scoped_release release;
    in = cli::prepare_input(request);
  }
  Record r;
  r.dt_s = in.motion.dt_s;
  r.accel_mps2 = numpy_copy(in.motion.ug_mps2);
  if (!in.motion.vg_mps2.empty()) r.vertical_mps2 = numpy_copy(in.motion.vg_mps2);
  r.path = in.horizontal.path;
  r.format = in.horizontal.format;
  r.units = in.horizontal.units;
  r.description = in.horizontal.description;
  r.source = in.horizontal.source;
  r.t0_s = in.horizontal.t0_s;
  r.notes = in.notes;
  return r;
}

// ------------------------------------------------------------------------------------------------------------- wall

struct Wall {
  options::WallChoice choice;
};

// The wall options' fields (b_m is --b, ...) over the paper wall or a wall file (--wall-file).
Wall make_wall(const std::optional<std::string>& wall_file, std::optional<double> b_m, std::optional<double> h1_m,
               std::optional<double> h2_m, std::optional<double> rho_kgpm3, std::optional<double> fp_npm,
               std::optional<double> a, std::optional<double> a_prime, std::optional<double> g_mps2) {
  const options::WallSettings s{std::nullopt, wall_file, b_m, h1_m, h2_m, rho_kgpm3, fp_npm, a, a_prime, g_mps2};
  return Wall{options::check_wall_settings(s)};
}

std::string wall_repr(const Wall& w) {
  const core::WallParameters& p = w.choice.wall;
  std::string text = "rockwatch.Wall(b_m=" + repr_number(p.b_m) + ", h1_m=" + repr_number(p.h1_m) +
                     ", h2_m=" + repr_number(p.h2_m) + ", rho_kgpm3=" + repr_number(p.rho_kgpm3) +
                     ", fp_npm=" + repr_number(p.fp_npm) + ", a=" + repr_number(p.a) +
                     ", a_prime=" + repr_number(p.a_prime) + ", g_mps2=" + repr_number(p.g_mps2);
  if (w.choice.wall_file_path) text += ", wall_file=" + options::quoted(*w.choice.wall_file_path);
  if (w.choice.r_from_file) text += ", r=" + repr_number(*w.choice.r_from_file);
  return text + ")";
}

// --------------------------------------------------------------------------------------------------------- simulate

// The result: the keys of `rockwatch simulate --json` as attributes (and as_dict()), the time history as arrays.
struct SimulateResult {};

// What `r` may be: "ana" | "exp" | "impulse" | a number, as --r.
std::variant<std::string, double> restitution_setting(const py::object& r) {
  if (py::isinstance<py::str>(r)) return r.cast<std::string>();
  if (py::isinstance<py::bool_>(r) || !(py::isinstance<py::float_>(r) || py::isinstance<py::int_>(r))) {
    throw py::type_error("r must be \"ana\", \"exp\", \"impulse\" or a number in [0, 1] (got " +
                         py::repr(r).cast<std::string>() + ")");
  }
  return r.cast<double>();
}

py::object simulate(const Array& accel_mps2, double dt_s, const std::optional<Wall>& wall_arg, const py::object& r,
                    const std::optional<Array>& vertical_mps2, const std::optional<double>& scale_pga_g,
                    const std::optional<double>& max_step_s, const std::optional<std::string>& arith, bool alarms,
                    const std::optional<std::string>& wall_sensors, const std::optional<double>& kappa,
                    const std::optional<std::string>& model, const std::optional<double>& t_end_s,
                    const std::optional<double>& lambda_w, const std::optional<double>& alarm_hold_s,
                    const std::optional<double>& energy_margin, const std::optional<double>& imminent_horizon_s,
                    const std::optional<double>& energy_min_x, bool history) {
  // The typed settings simulate's parser builds from its texts, checked by the same function (apply_simulate_settings).
  cli::SimulateSettings settings;
  if (wall_arg) settings.wall = wall_arg->choice;
  if (!r.is_none()) settings.r = restitution_setting(r);
  if (model) settings.model = *model;
  settings.scale_pga_g = scale_pga_g;
  settings.kappa = kappa;
  settings.max_step_s = max_step_s;
  settings.t_end_s = t_end_s;
  if (arith) settings.alarm.arith = *arith;
  settings.arith_given = arith.has_value();
  settings.alarm.alarms = alarms;
  settings.alarm.lambda_w = lambda_w;
  settings.alarm.hold_s = alarm_hold_s;
  settings.alarm.energy_margin = energy_margin;
  settings.alarm.imminent_horizon_s = imminent_horizon_s;
  settings.alarm.energy_min_x = energy_min_x;
  settings.keep_history = history;
  settings.history_kept_by = "keeping the history (history=True)";
  cli::SimulateRequest q;
  cli::apply_simulate_settings(settings, q);

  // The input as prepare_input makes it: the samples as given, both components scaled by one factor.
  sim::GroundMotion motion;
  motion.dt_s = options::check_positive_number("--dt", dt_s, " s");
  motion.ug_mps2 = vector_of(accel_mps2, "accel_mps2");
  if (motion.ug_mps2.size() < 2) {
    throw options::UsageError("accel_mps2 needs at least 2 samples (got " + std::to_string(motion.ug_mps2.size()) + ")");
  }
  if (vertical_mps2) {
    motion.vg_mps2 = vector_of(*vertical_mps2, "vertical_mps2");
    if (motion.vg_mps2.size() != motion.ug_mps2.size()) {
      throw options::UsageError("vertical_mps2 has " + std::to_string(motion.vg_mps2.size()) +
                                " samples and accel_mps2 " + std::to_string(motion.ug_mps2.size()) +
                                ": give both on one time grid (read_record(path, vertical=...) puts them on one)");
    }
  }
  if (q.scale_pga_g) {
    const double peak = sim::peak_abs(motion.ug_mps2);
    if (!(peak > 0.0)) {
      throw options::UsageError("--scale-pga: the horizontal record has peak |u''| = 0, so no factor can scale it to " +
                                options::number_text(*q.scale_pga_g) + " g");
    }
    const double factor = *q.scale_pga_g * q.wall.g_mps2 / peak;
    for (double& u : motion.ug_mps2) u *= factor;
    for (double& v : motion.vg_mps2) v *= factor;
  }

  cli::check_work_size(q, motion);

  std::vector<core::WallSensorSample> sensors;
  if (wall_sensors) {
    options::check_input_file("--wall-sensors", *wall_sensors, "a wall-sensor CSV file");
    q.wall_sensors_path = *wall_sensors;
    sensors = cli::read_wall_sensor_samples(*wall_sensors);
    q.analysis.wall_sensors = &sensors;
  }

  sim::AnalysisResult result;
  {
    py::gil_scoped_release release;
    result = sim::analyse(q.wall, motion, q.analysis);
  }
  q.analysis.wall_sensors = nullptr;

  py::object out = py::module_::import("rockwatch").attr("SimulateResult")();
  const Json j = cli::result_json(q, result);
  const py::dict dict = py::reinterpret_borrow<py::dict>(to_python(j));
  for (auto item : dict) py::setattr(out, item.first, item.second);
  py::setattr(out, "_keys", py::list(dict.attr("keys")()));
  py::setattr(out, "verdict", py::str(cli::verdict_word(result)));
  py::setattr(out, "n_impacts_total", py::int_(result.n_impacts_total));
  py::setattr(out, "t_end_s", py::float_(result.t_end_s));
  py::setattr(out, "t_final_s", py::float_(result.t_final_s));
  py::setattr(out, "free_motion_undecided", py::bool_(result.free_motion_undecided));
  py::list impacts;
  for (const sim::ImpactEvent& e : result.impacts) {
    impacts.append(py::dict(py::arg("t_s") = e.t_s, py::arg("v_before_mps") = e.v_before_mps,
                            py::arg("v_after_mps") = e.v_after_mps));
  }
  py::setattr(out, "impacts", impacts);
  py::setattr(out, "alarm_transitions",
              q.analysis.evaluate_alarm ? to_python(j["alarm"]["transitions"]) : py::object(py::list()));
  // The time history, one row per integration step (as `simulate --out`).
  const std::size_t n = result.history.size();
  const auto column = [&](auto member) {
    py::array_t<double> a(static_cast<py::ssize_t>(n));
    double* p = a.mutable_data();
    for (std::size_t i = 0; i < n; ++i) p[i] = static_cast<double>(result.history[i].*member);
    return a;
  };
  if (history) {
    py::setattr(out, "t_s", column(&sim::HistoryRow::t_s));
    py::setattr(out, "ug_mps2", column(&sim::HistoryRow::ug_mps2));
    py::setattr(out, "vg_mps2", column(&sim::HistoryRow::vg_mps2));
    py::setattr(out, "x_m", column(&sim::HistoryRow::x_m));
    py::setattr(out, "xd_mps", column(&sim::HistoryRow::xd_mps));
    py::setattr(out, "xdd_mps2", column(&sim::HistoryRow::xdd_mps2));
    py::setattr(out, "alpha1_rad", column(&sim::HistoryRow::alpha1_rad));
    py::setattr(out, "alpha2_rad", column(&sim::HistoryRow::alpha2_rad));
    py::setattr(out, "side", column(&sim::HistoryRow::side));
  }
  return out;
}

// ----------------------------------------------------------------------------------------------------- static check

// `rockwatch static --json` with these options: its JSON (an object for one instability factor, a list of two for
// code "both", the default).
py::object static_check(const std::optional<Wall>& wall, const std::optional<double>& b_m,
                        const std::optional<double>& h_m, const std::optional<double>& h1_m,
                        const std::optional<double>& h2_m, const std::optional<double>& fp_npm,
                        const std::optional<double>& a, const std::optional<double>& psi_rad,
                        const std::optional<double>& rho_kgpm3, const std::optional<double>& g_mps2,
                        const std::optional<double>& lambda, const std::optional<std::string>& code,
                        const std::optional<std::string>& spectrum, const std::optional<double>& p,
                        const std::optional<double>& tb_s, const std::optional<double>& tc_s,
                        const std::optional<double>& td_s) {
  cli::StaticSettings s{};
  if (wall) {  // the wall's fields, as if given (only h1 + h2, Fp, a, rho and g enter the static check)
    const core::WallParameters& w = wall->choice.wall;
    s.b_m = w.b_m;
    if (!h_m && !h1_m && !h2_m) {
      s.h1_m = w.h1_m;
      s.h2_m = w.h2_m;
    }
    s.fp_npm = w.fp_npm;
    if (w.fp_npm != 0.0) s.a = w.a;
    s.rho_kgpm3 = w.rho_kgpm3;
    s.g_mps2 = w.g_mps2;
  }
  // The keywords given replace the wall's fields.
  const std::pair<std::optional<double> cli::StaticSettings::*, const std::optional<double>*> fields[] = {
      {&cli::StaticSettings::b_m, &b_m},         {&cli::StaticSettings::h_m, &h_m},
      {&cli::StaticSettings::h1_m, &h1_m},       {&cli::StaticSettings::h2_m, &h2_m},
      {&cli::StaticSettings::fp_npm, &fp_npm},   {&cli::StaticSettings::a, &a},
      {&cli::StaticSettings::psi_rad, &psi_rad}, {&cli::StaticSettings::rho_kgpm3, &rho_kgpm3},
      {&cli::StaticSettings::g_mps2, &g_mps2},   {&cli::StaticSettings::lambda, &lambda},
      {&cli::StaticSettings::p, &p},             {&cli::StaticSettings::tb_s, &tb_s},
      {&cli::StaticSettings::tc_s, &tc_s},       {&cli::StaticSettings::td_s, &td_s}};
  for (const auto& [member, value] : fields) {
    if (*value) s.*member = *value;
  }
  s.code = code;
  s.spectrum = spectrum;
  s.json = true;
  const cli::StaticRequest q = cli::build_static_request(s);
  std::vector<core::StaticResult> results;
  for (const cli::StaticCase& c : q.cases) {
    core::StaticResult r;
    const core::StaticCheck check = core::run_static_check(cli::case_inputs(q, c), r);
    if (!check.ok()) throw options::UsageError(std::string("static check: ") + check.field + " " + check.message);
    results.push_back(r);
  }
  return to_python(cli::static_json(q, results));
}

// ------------------------------------------------------------------------------------------------ response spectrum

struct Spectrum {
  double damping = 0.0;
  py::array_t<double> periods_s, sd_m, psv_mps, psa_mps2, sa_abs_mps2;
  double pga_mps2 = 0.0, pgv_mps = 0.0, pgd_m = 0.0, arias_mps = 0.0;
  std::optional<double> d5_75_s, d5_95_s;
};

// `rockwatch spectrum`'s spectrum and intensity measures (sim::response_spectrum, sim::intensity_measures) of the
// samples. periods_s: None (0.02 to 4 s, 100 log-spaced), "FROM:TO:N" as --periods, or the periods themselves.
Spectrum response_spectrum(const Array& accel_mps2, double dt_s, const py::object& periods_s,
                           const std::optional<double>& damping, double g_mps2) {
  const std::vector<double> a = vector_of(accel_mps2, "accel_mps2");
  std::vector<double> periods;
  if (periods_s.is_none()) {
    periods = sim::default_spectrum_periods();
  } else if (py::isinstance<py::str>(periods_s)) {
    const cli::PeriodGrid grid = cli::parse_period_grid("--periods", periods_s.cast<std::string>());
    periods = sim::log_spaced_periods(grid.from_s, grid.to_s, grid.count);
  } else {
    periods = vector_of(periods_s.cast<Array>(), "periods_s");
  }
  const double zeta = damping.value_or(core::kDefaultDampingRatio);
  Spectrum out;
  sim::ResponseSpectrum rs;
  sim::IntensityMeasures im;
  {
    py::gil_scoped_release release;
    rs = sim::response_spectrum(a, dt_s, periods, zeta);
    im = sim::intensity_measures(a, dt_s, g_mps2);
  }
  out.damping = rs.damping;
  out.periods_s = numpy_copy(rs.periods_s);
  out.sd_m = numpy_copy(rs.sd_m);
  out.psv_mps = numpy_copy(rs.psv_mps);
  out.psa_mps2 = numpy_copy(rs.psa_mps2);
  out.sa_abs_mps2 = numpy_copy(rs.sa_abs_mps2);
  out.pga_mps2 = im.pga_mps2;
  out.pgv_mps = im.pgv_mps;
  out.pgd_m = im.pgd_m;
  out.arias_mps = im.arias_mps;
  out.d5_75_s = im.d5_75_s;
  out.d5_95_s = im.d5_95_s;
  return out;
}

// --------------------------------------------------------------------------------------------------------- identify

// `rockwatch identify --json` on these files: its JSON as a dict, plus the fitted curve (t_s, measured_m, fitted_m).
py::object identify(const std::string& wall_sensors, const std::optional<std::string>& record,
                    const std::optional<std::string>& units, const std::optional<double>& dt_s,
                    const std::optional<std::string>& channel, const std::optional<std::string>& component,
                    const std::optional<double>& scale_pga_g, const std::optional<Wall>& wall, const py::object& r,
                    const std::optional<double>& max_step_s, const std::optional<std::string>& wall_out,
                    const std::optional<long long>& bootstrap, const std::optional<unsigned long long>& bootstrap_seed,
                    const std::optional<long long>& jobs) {
  cli::IdentifySettings s;
  s.wall_sensors = wall_sensors;
  s.record.record = record;  // identify's record options, as read_record's
  s.record.units = units;
  s.record.dt_s = dt_s;
  s.record.channel = channel;
  s.record.component = component;
  s.scale_pga_g = scale_pga_g;
  if (wall) s.wall = wall->choice;
  if (!r.is_none()) s.r = restitution_setting(r);
  s.max_step_s = max_step_s;
  s.wall_out = wall_out;
  s.bootstrap = bootstrap;
  s.bootstrap_seed = bootstrap_seed;
  s.jobs = jobs;
  s.json = true;
  const cli::IdentifyRequest q = cli::build_identify_request(s);
  // As the command runs it (identify_command.cpp).
  sim::IdentificationInput in = cli::identification_input(q);
  sim::IdentificationResult result;
  {
    py::gil_scoped_release release;
    in.samples = cli::read_wall_sensor_samples(q.wall_sensors_path);
    std::optional<cli::InputMotion> motion;
    if (q.record) {
      motion = cli::prepare_input(cli::InputRequest{*q.record, q.scale_pga_g, q.start_wall.g_mps2});
      in.ground = &motion->motion;
    }
    try {
      result = sim::identify(in);
    } catch (const sim::IdentificationError& e) {
      throw options::UsageError("the record does not identify the wall: " + std::string(e.what()) + " (" +
                                q.wall_sensors_path + ")");
    }
  }
  if (q.wall_out_path) {
    const options::WallFile file = cli::identified_wall_file(q, result);
    cli::write_output_file(*q.wall_out_path,
                           [&](std::ostream& out) { out << options::wall_file_json(file).dump(2) << '\n'; });
  }
  py::dict d = py::reinterpret_borrow<py::dict>(to_python(cli::identify_json(q, result, in.start_r)));
  d["t_s"] = numpy_copy(result.t_s);
  d["measured_m"] = numpy_copy(result.measured_m);
  d["fitted_m"] = numpy_copy(result.fitted_m);
  return std::move(d);
}

}  // namespace

}  // namespace rockwatch::python

PYBIND11_MODULE(rockwatch, m) {
  using namespace rockwatch;
  using namespace rockwatch::python;
  m.doc() = "rockwatch: out-of-plane rocking of unreinforced masonry walls (the engine of the rockwatch tool). "
            "See docs/python.md.";
  m.attr("__version__") = ROCKWATCH_VERSION;

  // The tool's "error: MESSAGE" (exit 2) is ValueError(MESSAGE).
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const options::UsageError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const records::RecordError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const sim::AnalysisError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const sim::MeasureError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const sim::IdentificationError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  py::class_<Record>(m, "Record", "A ground-motion record as rockwatch reads it (SI units, the file's sign)")
      .def_readonly("dt_s", &Record::dt_s, "sample interval [s]")
      .def_readonly("accel_mps2", &Record::accel_mps2, "horizontal (out-of-plane) ground acceleration [m/s2]")
      .def_readonly("vertical_mps2", &Record::vertical_mps2,
                    "vertical acceleration [m/s2, up +] on the horizontal's time grid, or None")
      .def_readonly("path", &Record::path)
      .def_readonly("format", &Record::format, "the reader: peer-at2, plain, esm, itaca-cor-acc, miniseed, rockwatch-suite")
      .def_readonly("units", &Record::units, "the units the values were converted from")
      .def_readonly("description", &Record::description, "header text of the file")
      .def_readonly("source", &Record::source, "channel or component read")
      .def_readonly("t0_s", &Record::t0_s, "time of the first sample in the file [s]")
      .def_readonly("notes", &Record::notes, "the readers' notes (rockwatch prints them on stderr)")
      .def("__len__", [](const Record& r) { return r.accel_mps2.size(); })
      .def("__repr__", [](const Record& r) {
        return "<rockwatch.Record " + r.path + ": " + r.format + ", " + std::to_string(r.accel_mps2.size()) +
               " samples at dt " + options::number_text(r.dt_s) + " s" +
               (r.vertical_mps2.is_none() ? std::string() : std::string(", with vertical")) + ">";
      });

  m.def("read_record", &read_record, py::arg("path"), py::kw_only(), py::arg("units") = py::none(),
        py::arg("dt_s") = py::none(), py::arg("gain_counts_per_mps2") = py::none(), py::arg("channel") = py::none(),
        py::arg("component") = py::none(), py::arg("vertical") = py::none(), py::arg("vertical_channel") = py::none(),
        py::arg("g_mps2") = 9.81,
        "Reads a record as `rockwatch simulate --record PATH` does (PEER AT2, ESM, ITACA, miniSEED, suite set files, "
        "plain columns; detected from the content). Options as simulate's: units (--units), dt_s (--dt), "
        "gain_counts_per_mps2 (--gain), channel (--channel), component (--component), vertical (--vertical FILE, "
        "resampled onto this record's grid), vertical_channel, g_mps2 (converts records in g).");

  py::class_<Wall>(m, "Wall", "A two-block wall (SPEC 1, per metre of wall): the paper wall with the given fields")
      .def(py::init([](std::optional<double> b_m, std::optional<double> h1_m, std::optional<double> h2_m,
                       std::optional<double> rho_kgpm3, std::optional<double> fp_npm, std::optional<double> a,
                       std::optional<double> a_prime, std::optional<double> g_mps2) {
             return make_wall(std::nullopt, b_m, h1_m, h2_m, rho_kgpm3, fp_npm, a, a_prime, g_mps2);
           }),
           py::kw_only(), py::arg("b_m") = py::none(), py::arg("h1_m") = py::none(), py::arg("h2_m") = py::none(),
           py::arg("rho_kgpm3") = py::none(), py::arg("fp_npm") = py::none(), py::arg("a") = py::none(),
           py::arg("a_prime") = py::none(), py::arg("g_mps2") = py::none(),
           "The paper wall (Table 2) with the fields given replaced (simulate's --b, --h1, --h2, --rho, --fp, --a, "
           "--a-prime, --g), checked as the tool checks them.")
      .def_static("paper", [] { return Wall{}; }, "The design paper's wall (Table 2): the tool's --wall paper")
      .def_static("from_file",
                  [](const std::string& path, std::optional<double> b_m, std::optional<double> h1_m,
                     std::optional<double> h2_m, std::optional<double> rho_kgpm3, std::optional<double> fp_npm,
                     std::optional<double> a, std::optional<double> a_prime, std::optional<double> g_mps2) {
                    return make_wall(path, b_m, h1_m, h2_m, rho_kgpm3, fp_npm, a, a_prime, g_mps2);
                  },
                  py::arg("path"), py::kw_only(), py::arg("b_m") = py::none(), py::arg("h1_m") = py::none(),
                  py::arg("h2_m") = py::none(), py::arg("rho_kgpm3") = py::none(), py::arg("fp_npm") = py::none(),
                  py::arg("a") = py::none(), py::arg("a_prime") = py::none(), py::arg("g_mps2") = py::none(),
                  "A wall file (rockwatch identify --wall-out; --wall-file): its wall and its r, which simulate uses "
                  "unless given r")
      .def_property_readonly("b_m", [](const Wall& w) { return w.choice.wall.b_m; })
      .def_property_readonly("h1_m", [](const Wall& w) { return w.choice.wall.h1_m; })
      .def_property_readonly("h2_m", [](const Wall& w) { return w.choice.wall.h2_m; })
      .def_property_readonly("rho_kgpm3", [](const Wall& w) { return w.choice.wall.rho_kgpm3; })
      .def_property_readonly("fp_npm", [](const Wall& w) { return w.choice.wall.fp_npm; })
      .def_property_readonly("a", [](const Wall& w) { return w.choice.wall.a; })
      .def_property_readonly("a_prime", [](const Wall& w) { return w.choice.wall.a_prime; })
      .def_property_readonly("g_mps2", [](const Wall& w) { return w.choice.wall.g_mps2; })
      .def_property_readonly("r", [](const Wall& w) { return w.choice.r_from_file; },
                             "the wall file's energy ratio at impact, or None")
      .def_property_readonly("wall_file", [](const Wall& w) { return w.choice.wall_file_path; })
      .def("__repr__", &wall_repr);

  py::class_<SimulateResult>(m, "SimulateResult", py::dynamic_attr(),
                             "What `rockwatch simulate --json` prints, its keys as attributes; the time history as "
                             "arrays (t_s, x_m, xd_mps, ...); alarm_transitions a list of dicts")
      .def(py::init<>())
      .def("keys", [](py::object self) { return self.attr("_keys"); }, "the keys of simulate --json, in its order")
      .def("as_dict",
           [](py::object self) {
             py::dict d;
             for (auto key : self.attr("_keys")) d[key] = self.attr(key);
             return d;
           },
           "the object simulate --json prints")
      .def("__repr__", [](py::object self) {
        return "<rockwatch.SimulateResult " + self.attr("verdict").cast<std::string>() + ", max_abs_x_m=" +
               py::repr(self.attr("max_abs_x_m")).cast<std::string>() + ">";
      });

  m.def("simulate", &simulate, py::arg("accel_mps2"), py::arg("dt_s"), py::kw_only(), py::arg("wall") = py::none(),
        py::arg("r") = py::none(), py::arg("vertical_mps2") = py::none(), py::arg("scale_pga_g") = py::none(),
        py::arg("max_step_s") = py::none(), py::arg("arith") = py::none(), py::arg("alarms") = false,
        py::arg("wall_sensors") = py::none(), py::arg("kappa") = py::none(), py::arg("model") = py::none(),
        py::arg("t_end_s") = py::none(), py::arg("lambda_w") = py::none(), py::arg("alarm_hold_s") = py::none(),
        py::arg("energy_margin") = py::none(), py::arg("imminent_horizon_s") = py::none(),
        py::arg("energy_min_x") = py::none(), py::arg("history") = true,
        "Runs a wall through a ground motion as `rockwatch simulate --json` does (the same engine and defaults). "
        "accel_mps2: horizontal samples [m/s2] every dt_s; wall: a Wall (default the paper's); r: --r (\"ana\", "
        "\"exp\", \"impulse\" or a number; default exp, or the wall file's); vertical_mps2 on the same grid; "
        "scale_pga_g: --scale-pga; max_step_s: --max-step; arith: \"double\" | \"fixed\"; alarms: --alarms; "
        "wall_sensors: --wall-sensors FILE.csv; kappa, model, t_end_s, lambda_w, alarm_hold_s, energy_margin: the "
        "options of those names; imminent_horizon_s: --imminent-horizon; energy_min_x: --energy-min-x; "
        "history=False skips the time history.");

  m.def("static_check", &static_check, py::kw_only(), py::arg("wall") = py::none(), py::arg("b_m") = py::none(),
        py::arg("h_m") = py::none(), py::arg("h1_m") = py::none(), py::arg("h2_m") = py::none(),
        py::arg("fp_npm") = py::none(), py::arg("a") = py::none(), py::arg("psi_rad") = py::none(),
        py::arg("rho_kgpm3") = py::none(), py::arg("g_mps2") = py::none(), py::arg("lambda_") = py::none(),
        py::arg("code") = py::none(), py::arg("spectrum") = py::none(), py::arg("p") = py::none(),
        py::arg("tb_s") = py::none(), py::arg("tc_s") = py::none(), py::arg("td_s") = py::none(),
        "The static non-linear kinematic check (SPEC 5) as `rockwatch static --json`: a dict (T_s, x_eq_max_m, "
        "allowable_pga_g, K, X_m, lambda, ...) for one instability factor (code=\"ntc2008\" | \"nzsee2016\" or "
        "lambda_=L), a list of two for code=\"both\" (the default). wall: a Wall for b, h1, h2, Fp, a, rho, g; the "
        "other arguments are static's options (--b, --h, --h1, --h2, --fp, --a, --psi, --rho, --g, --lambda, --code, "
        "--spectrum, --p, --tb, --tc, --td).");

  py::class_<Spectrum>(m, "Spectrum", "Elastic response spectrum and intensity measures of a record")
      .def_readonly("damping", &Spectrum::damping)
      .def_readonly("periods_s", &Spectrum::periods_s)
      .def_readonly("sd_m", &Spectrum::sd_m, "spectral displacement")
      .def_readonly("psv_mps", &Spectrum::psv_mps, "pseudo-spectral velocity")
      .def_readonly("psa_mps2", &Spectrum::psa_mps2, "pseudo-spectral acceleration (spectrum --json's sa_mps2)")
      .def_property_readonly("sa_mps2", [](const Spectrum& s) { return s.psa_mps2; }, "= psa_mps2, as spectrum --json")
      .def_readonly("sa_abs_mps2", &Spectrum::sa_abs_mps2, "peak absolute acceleration")
      .def_readonly("pga_mps2", &Spectrum::pga_mps2)
      .def_readonly("pgv_mps", &Spectrum::pgv_mps, "baseline-corrected")
      .def_readonly("pgd_m", &Spectrum::pgd_m, "baseline-corrected")
      .def_readonly("arias_mps", &Spectrum::arias_mps)
      .def_readonly("d5_75_s", &Spectrum::d5_75_s)
      .def_readonly("d5_95_s", &Spectrum::d5_95_s);
  m.def("response_spectrum", &response_spectrum, py::arg("accel_mps2"), py::arg("dt_s"),
        py::arg("periods_s") = py::none(), py::kw_only(), py::arg("damping") = py::none(), py::arg("g_mps2") = 9.81,
        "The response spectrum and intensity measures of `rockwatch spectrum` (sim::response_spectrum, "
        "sim::intensity_measures). periods_s: None (0.02 to 4 s, 100 log-spaced: spectrum's default), "
        "\"FROM:TO:N\" as --periods, or an array of periods; damping: the ratio (default 0.05).");

  m.def("identify", &identify, py::arg("wall_sensors"), py::kw_only(), py::arg("record") = py::none(),
        py::arg("units") = py::none(), py::arg("dt_s") = py::none(), py::arg("channel") = py::none(),
        py::arg("component") = py::none(), py::arg("scale_pga_g") = py::none(), py::arg("wall") = py::none(),
        py::arg("r") = py::none(), py::arg("max_step_s") = py::none(), py::arg("wall_out") = py::none(),
        py::arg("bootstrap") = py::none(), py::arg("bootstrap_seed") = py::none(), py::arg("jobs") = py::none(),
        "Identifies a wall from a test as `rockwatch identify --json` (sim::identify): wall_sensors the transducer's "
        "CSV, record the ground motion of a forced test (None: a snap-back test), wall the starting wall, r the start "
        "of r, wall_out a wall file to write (Wall.from_file reads it), bootstrap N refits whose spread is the "
        "standard error (--bootstrap; a forced test needs it), bootstrap_seed, jobs its threads. Returns identify --json's dict, with the "
        "fitted curve as arrays t_s, measured_m, fitted_m.");

  add_study_module(m);
}
