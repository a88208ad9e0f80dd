// `rockwatch demo`, the main job: rockwatch-monitor watches the paper's wall live over LCM (multicast on this
// machine) while two suite records are replayed to it in real time, one that collapses the wall and one it
// survives; its alarm timeline is printed beside the offline fixed-point simulation of the very same samples.
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <system_error>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "common/process/command_runner.hpp"
#include "common/process/commands.hpp"
#include "common/records_in/input_motion.hpp"
#include "common/replay_out/lcm_multicast.hpp"
#include "common/process/progress_line.hpp"
#include "common/records_in/record_selection.hpp"
#include "common/replay_out/replay_publisher.hpp"
#include "common/replay_out/replay_stream.hpp"
#include "common/process/signal_interrupt.hpp"
#include "common/records_in/wall_sensors.hpp"
#include "demo/demo_monitor.hpp"
#include "demo/demo_request.hpp"
#include "demo/demo_timeline.hpp"
#include "rockwatch/core/alarm.hpp"
#include "rockwatch/core/model.hpp"
#include "rockwatch/core/wall.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "rockwatch/sim/wall_sensor_synthesis.hpp"

namespace rockwatch::cli {

namespace {

constexpr CommandErrors kErrors{"rockwatch demo: error: ", "out of memory"};
constexpr const char* kListeningMarker = "listening on";
constexpr double kMonitorStartTimeout_s = 10.0;
constexpr double kMonitorStopTimeout_s = 5.0;
constexpr long kDrainMs = 300;  // after the last sample, before the monitor is stopped: loopback delivery is sub-ms

std::string decimals(double value, int digits) {
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", digits, value);
  return text;
}

// The directory for the run's files: --out DIR (kept), else a temporary one (removed).
class WorkDir {
 public:
  explicit WorkDir(const std::optional<std::string>& out) {
    std::error_code ec;
    if (out) {
      std::filesystem::create_directories(*out, ec);
      if (ec || !std::filesystem::is_directory(*out)) {
        throw UsageError("--out " + *out + ": cannot create the directory" +
                         (ec ? ": " + ec.message() : std::string()));
      }
      path_ = *out;
      return;
    }
    std::string pattern = (std::filesystem::temp_directory_path(ec) / "rockwatch_demo.XXXXXX").string();
    std::vector<char> buffer(pattern.begin(), pattern.end());
    buffer.push_back('\0');
    if (mkdtemp(buffer.data()) == nullptr)
      throw std::runtime_error("cannot create a temporary directory" + system_reason());
    path_ = buffer.data();
    temporary_ = true;
  }
  ~WorkDir() {
    std::error_code ec;
    if (temporary_) std::filesystem::remove_all(path_, ec);
  }
  WorkDir(const WorkDir&) = delete;
  WorkDir& operator=(const WorkDir&) = delete;
  std::string file(const std::string& name) const { return (std::filesystem::path(path_) / name).string(); }

 private:
  std::string path_;
  bool temporary_ = false;
};

// The shipped suite's set 3 at 0.25 g: component Y collapses the paper wall (t = 3.06 s), X does not (max |x| 0.52
// x_inst). Other sets and PGAs run the same two components; the offline verdict says what each does.
constexpr char kComponents[] = {'Y', 'X'};

struct CaseResult {
  std::string title;
  bool match = false;
  bool monitor_ok = false;
  std::string verdict;  // offline
  std::string monitor_max_level;
  TimelineComparison comparison;
};

std::string offline_verdict(const OfflineRun& run) {
  const sim::AnalysisResult& r = run.result;
  if (r.collapsed) return "collapses at t = " + decimals(*r.t_collapse_s, 3) + " s";
  if (r.collapse_after_end) return "collapses after the record ends";
  return "survives: max |x| " + decimals(r.max_abs_x_m, 4) + " m = " + decimals(r.max_abs_x_m / r.x_inst_m, 2) +
         " x_inst";
}

// The highest level of a timeline by the alarm's order (QUIET < ROCKING < ... < COLLAPSED); QUIET when empty.
std::string highest_level(const std::vector<TimelineEntry>& timeline) {
  int best = 0;
  for (const TimelineEntry& e : timeline) {
    for (int level = 0; level <= static_cast<int>(core::AlarmLevel::collapsed); ++level) {
      if (e.level == core::alarm_level_name(static_cast<core::AlarmLevel>(level)) && level > best) best = level;
    }
  }
  return core::alarm_level_name(static_cast<core::AlarmLevel>(best));
}

std::string counters_text(const nlohmann::json& summary) {
  if (!summary.contains("counters") || !summary["counters"].is_object()) return "no counters";
  const nlohmann::json& c = summary["counters"];
  const auto count = [&c](const char* key) {
    return c.contains(key) && c[key].is_number_integer() ? std::to_string(c[key].get<std::int64_t>())
                                                         : std::string("?");
  };
  return count("samples_received") + " samples received, " + count("samples_processed") + " processed, " +
         count("gaps") + " gaps, " + count("late") + " late, " + count("out_of_order") + " out of order";
}

std::int64_t counter(const std::optional<nlohmann::json>& summary, const char* key) {
  if (!summary || !summary->contains("counters")) return -1;
  const nlohmann::json& c = (*summary)["counters"];
  return c.contains(key) && c[key].is_number_integer() ? c[key].get<std::int64_t>() : -1;
}

void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

class Demo {
 public:
  Demo(const DemoRequest& q, const MonitorLocation& monitor, const WorkDir& work, const SignalInterrupt& interrupt)
      : q_(q), monitor_(monitor), work_(work), interrupt_(interrupt) {}

  // The offline runs' options: the monitor's restitution (r_exp, or the wall file's r).
  sim::AnalysisOptions nominal_options() const {
    sim::AnalysisOptions o;
    o.restitution = q_.restitution;
    return o;
  }

  CaseResult run_case(char component, int index, int total) {
    CaseResult result;
    const std::string name = "set" + std::string(q_.set < 10 ? "0" : "") + std::to_string(q_.set) + "_" + component;
    result.title = "set " + std::to_string(q_.set) + " component " + component;

    const ReplayStream stream = suite_stream(component);
    const sim::GroundMotion motion = stream_motion(stream, stream.size());
    const OfflineRun offline = run_offline(q_.wall, motion, nominal_options());
    result.verdict = offline_verdict(offline);

    std::cout << "\n== " << index << "/" << total << "  " << result.title << " at PGA " << number_text(q_.pga_g)
              << " g: " << stream.size() << " samples, " << decimals(stream.duration_s(), 3) << " s\n"
              << "  offline (fixed-point engine, same samples): " << result.verdict << "\n"
              << std::flush;

    const LiveRun live = run_live(name, stream, {}, nullptr);
    if (!live.started) return result;
    const MonitorOutput& out = live.output;
    result.monitor_ok = live.clean && out.summary.has_value();
    result.monitor_max_level = highest_level(out.transitions);
    if (offline.after_record > 0) {
      std::cout << "  (the offline run has " << offline.after_record
                << " more transitions in the free motion after the record; the monitor gets no samples there)\n";
    }
    std::cout << "\n" << side_by_side(out.transitions, offline.transitions, "  ");
    result.comparison = compare_timelines(out.transitions, offline.transitions);
    result.match = result.monitor_ok && result.comparison.match;
    if (result.comparison.match) {
      std::cout << "  match: yes, the same " << out.transitions.size() << " transitions, "
                << result.comparison.same_sample << " in the same sample, " << result.comparison.next_sample
                << " in the next\n";
    } else {
      std::cout << "  match: NO, " << result.comparison.reason << "\n";
    }
    if (q_.out_dir) {
      write_samples_file(work_.file(name + "_samples.csv"), stream);
      write_text(work_.file(name + "_timeline.txt"), side_by_side(out.transitions, offline.transitions, ""));
    }
    std::cout << std::flush;
    return result;
  }

  // The instrumented wall: the real wall dissipates like r_ana (paper eq. 17), the monitor's nominal wall assumes
  // r_exp = 0.9 r_ana, as a monitor configured from the paper's own experimental value would. The wall carries a
  // displacement transducer at the mid-height hinge (0.5 mm noise, 2 mm zero offset), simulated from the true wall's
  // response. Three timelines: the truth, the nominal wall open loop (what the monitor says without sensors) and the
  // live monitor fused with the sensors (--observer), which must equal the offline fused run of the same samples.
  // What an instrumented case's real wall is, against the monitor's nominal one.
  struct TrueWall {
    std::string suffix;          // of the file names: "instrumented", "thinner"
    std::string title;           // "instrumented wall", "a wall 10 % thinner than its drawings"
    core::WallParameters wall;   // the real wall
    core::Restitution restitution;
    std::string truth_label;     // the truth's column: "truth (r_ana)"
    std::string what;            // the line that says how the real wall differs
    double pga_g = 0.0;
  };

  CaseResult run_instrumented_case(char component, int index, int total) {
    TrueWall t;
    t.suffix = "instrumented";
    t.title = "instrumented wall";
    t.wall = q_.wall;
    t.restitution = core::Restitution{core::RestitutionKind::ana, 0.0};
    t.truth_label = "truth (r_ana)";
    t.pga_g = q_.pga_g;
    return run_true_wall_case(component, index, total, t);
  }

  // A wall 10 % thinner than its drawings (the effective thickness of a real wall: mortar crushing at the hinges),
  // r_exp of its own geometry, on the same set's component Y at 0.72 x --pga (0.18 g by default: the thinner wall
  // collapses, the nominal one survives). The monitor is told the drawings' wall; with the transducer it estimates the
  // wall's capacity (x_inst) as it rocks, and alarms on the estimated wall.
  CaseResult run_thinner_wall_case(char component, int index, int total) {
    TrueWall t;
    t.suffix = "thinner";
    t.title = "a wall 10 % thinner than its drawings";
    t.wall = q_.wall;
    t.wall.b_m = 0.9 * q_.wall.b_m;
    t.restitution = core::Restitution{};
    t.truth_label = "truth (0.9 b)";
    t.pga_g = 0.72 * q_.pga_g;
    return run_true_wall_case(component, index, total, t);
  }

  CaseResult run_true_wall_case(char component, int index, int total, const TrueWall& t) {
    CaseResult result;
    const std::string name = "set" + std::string(q_.set < 10 ? "0" : "") + std::to_string(q_.set) + "_" + component +
                             "_" + t.suffix;
    result.title = t.title + ", set " + std::to_string(q_.set) + " component " + component;
    const ReplayStream stream = suite_stream(component, t.pga_g);
    const sim::GroundMotion motion = stream_motion(stream, stream.size());
    const core::WallParameters wall = q_.wall;
    const OfflineRun truth = run_truth(t.wall, motion, t.restitution);
    sim::SensorModel sensor;
    sensor.rate_hz = q_.rate_hz;
    sensor.x_noise_m = 0.5e-3;
    sensor.x_bias_m = 2e-3;
    sensor.seed = 1;
    const std::vector<core::WallSensorSample> sensors =
        sim::synthesize_wall_sensors(t.wall, truth.result, motion.dt_s, sensor);
    const OfflineRun open_loop = run_offline(wall, motion, nominal_options());
    sim::AnalysisOptions fused_options = nominal_options();
    fused_options.wall_sensors = &sensors;
    const OfflineRun fused = run_offline(wall, motion, fused_options);
    result.verdict = "true wall " + offline_verdict(truth);

    std::cout << "\n== " << index << "/" << total << "  " << result.title << " at PGA " << number_text(t.pga_g) << " g: ";
    if (t.suffix == "instrumented") {
      std::cout << "the real wall has r = r_ana = " << decimals(truth.result.r, 4) << ", the monitor assumes r_exp = "
                << decimals(open_loop.result.r, 4) << "\n";
    } else {
      std::cout << "the real wall is " << decimals(t.wall.b_m, 3) << " m thick (x_inst "
                << decimals(truth.result.x_inst_m, 4) << " m), the monitor is told " << decimals(wall.b_m, 3)
                << " m (x_inst " << decimals(open_loop.result.x_inst_m, 4) << " m)\n";
    }
    std::cout
              << "  sensors on the wall: a displacement transducer at the mid-height hinge, " << sensors.size()
              << " samples at " << number_text(q_.rate_hz) << " Hz, noise 0.5 mm, zero offset 2 mm\n"
              << "  " << t.truth_label << ", double engine: " << offline_verdict(truth) << "\n"
              << "  open loop (the monitor without sensors, offline): " << offline_verdict(open_loop) << "\n"
              << "  fused (offline, same samples): " << offline_verdict(fused) << "; r estimate "
              << decimals(fused.result.observer.r_estimate, 4) << ", x_inst estimate "
              << decimals(fused.result.observer.x_inst_estimate_m, 4) << " m, offset "
              << decimals(fused.result.observer.bias_estimate_m * 1e3, 2) << " mm\n"
              << std::flush;

    const LiveRun live = run_live(name, stream, {"--observer"}, &sensors);
    if (!live.started) return result;
    const MonitorOutput& out = live.output;
    result.monitor_ok = live.clean && out.summary.has_value();
    result.monitor_max_level = highest_level(out.transitions);
    if (out.summary && out.summary->contains("observer")) {
      const nlohmann::json& o = (*out.summary)["observer"];
      std::cout << "  monitor's observer: r estimate " << decimals(o.value("r_estimate", 0.0), 4) << " (true "
                << decimals(truth.result.r, 4) << ", nominal " << decimals(open_loop.result.r, 4) << "), offset "
                << decimals(o.value("bias_estimate_m", 0.0) * 1e3, 2) << " mm (true 2.00)";
      if (o.contains("x_inst_estimate_m") && o["x_inst_estimate_m"].is_number()) {
        std::cout << ", x_inst estimate " << decimals(o["x_inst_estimate_m"].get<double>(), 4) << " m (true "
                  << decimals(truth.result.x_inst_m, 4) << ", nominal " << decimals(open_loop.result.x_inst_m, 4) << ")";
      }
      std::cout << "\n";
    }
    std::cout << "\n"
              << columns_text({{t.truth_label, truth.transitions},
                               {"open loop (nominal)", open_loop.transitions},
                               {"monitor fused", out.transitions}},
                              "  ");
    result.comparison = compare_timelines(out.transitions, fused.transitions);
    result.match = result.monitor_ok && result.comparison.match;
    const auto first_at = [](const std::vector<TimelineEntry>& timeline, const char* level) -> std::optional<double> {
      for (const TimelineEntry& e : timeline) {
        if (e.level == level) return e.t_s;
      }
      return std::nullopt;
    };
    const std::optional<double> collapse = truth.result.t_collapse_s;
    const std::optional<double> imminent = first_at(out.transitions, "IMMINENT");
    if (collapse && imminent && *imminent <= *collapse) {
      std::cout << "  the fused monitor said IMMINENT " << decimals(*collapse - *imminent, 2)
                << " s before the real wall collapsed; open loop its highest level was "
                << highest_level(open_loop.transitions) << "\n";
    }
    if (result.comparison.match) {
      std::cout << "  live = offline fused: yes, the same " << out.transitions.size() << " transitions, "
                << result.comparison.same_sample << " in the same sample, " << result.comparison.next_sample
                << " in the next\n";
    } else {
      std::cout << "  live = offline fused: NO, " << result.comparison.reason << "\n";
    }
    if (q_.out_dir) {
      std::ofstream csv(work_.file(name + "_wall_sensors.csv"), std::ios::binary);
      write_wall_sensor_csv(csv, sensors, false);
      write_text(work_.file(name + "_timeline.txt"),
                 columns_text({{t.truth_label, truth.transitions},
                               {"open loop (nominal)", open_loop.transitions},
                               {"monitor fused", out.transitions}},
                              ""));
    }
    std::cout << std::flush;
    return result;
  }

  struct LiveRun {
    bool started = false;     // the monitor ran and the replay went through (not interrupted)
    bool clean = false;       // the monitor stopped by itself after SIGINT
    MonitorOutput output;     // its transitions and summary
    ReplayOutcome outcome;
  };

  // A fresh monitor (the wall at rest, seq from 0) with `extra` arguments; the stream (and the wall's sensors, when
  // given) replayed to it in real time; its output read back. Prints what happened.
  LiveRun run_live(const std::string& name, const ReplayStream& stream, const std::vector<std::string>& extra,
                   const std::vector<core::WallSensorSample>* wall_sensors) {
    LiveRun live;
    const std::string out_path = work_.file(name + "_monitor.jsonl"), err_path = work_.file(name + "_monitor.err");
    std::vector<std::string> arguments{"--lcm-url", q_.lcm_url, "--rate", number_text(q_.rate_hz), "--kappa", "2"};
    if (q_.wall_file) {
      arguments.insert(arguments.end(), {"--wall-file", *q_.wall_file});  // its wall and r
    } else {
      arguments.insert(arguments.end(), {"--r", "exp"});
    }
    arguments.insert(arguments.end(), extra.begin(), extra.end());
    if (q_.monitor_config) {
      arguments.emplace_back("--config");
      arguments.push_back(*q_.monitor_config);
    }
    MonitorProcess monitor(monitor_.path, arguments, out_path, err_path);
    if (!monitor.wait_for_marker(kListeningMarker, kMonitorStartTimeout_s)) {
      if (!monitor.running()) {
        std::cout << "  the monitor ended at start (" << monitor.exit_text() << "):\n" << file_text(err_path);
        return live;
      }
      std::cerr << "note: the monitor did not say it listens within " << kMonitorStartTimeout_s
                << " s; replaying anyway\n";
    }
    std::cout << "  monitor: started (pid " << monitor.pid() << "), listening\n" << std::flush;

    std::string problem;
    const std::unique_ptr<lcm::LCM> lcm = open_lcm(q_.lcm_url, problem);
    if (!lcm) throw UsageError(problem);
    PublishPlan plan;
    plan.channel = kAccelChannel;
    plan.speed = q_.speed;
    plan.wall_sensors = wall_sensors;
    ReplayOutcome& outcome = live.outcome;
    {
      ProgressLine progress(std::cerr, stderr_is_terminal());
      const std::size_t n = stream.size();
      outcome = publish_stream(stream, plan, lcm.get(), nullptr, interrupt_.flag(),
                               [&progress, n, &name](std::size_t done, double elapsed_s) {
                                 progress.update(name + " " + progress_bar_text(done, n, elapsed_s));
                               });
    }
    if (outcome.interrupted || outcome.aborted) {
      monitor.stop(kMonitorStopTimeout_s);
      if (outcome.aborted) throw UsageError("LCM could not send on " + q_.lcm_url + ": " + outcome.first_failure);
      return live;
    }
    std::cout << "  replay: " << outcome.samples_sent << " ground_accel_t at " << number_text(q_.rate_hz) << " Hz"
              << (wall_sensors != nullptr
                      ? " and " + std::to_string(outcome.wall_sensor_samples_sent) + " wall_sensor_t"
                      : std::string())
              << (q_.speed == 1.0 ? std::string(", real time") : ", speed " + number_text(q_.speed)) << ", "
              << decimals(outcome.elapsed_s, 2) << " s; lateness p50 " << microseconds_text(outcome.lateness.p50_us)
              << ", p99 " << microseconds_text(outcome.lateness.p99_us) << ", max "
              << microseconds_text(outcome.lateness.max_us) << "\n";

    usleep(static_cast<useconds_t>(kDrainMs * 1000));
    live.clean = monitor.stop(kMonitorStopTimeout_s);
    live.output = parse_monitor_output(file_text(out_path), outcome.start_utime, q_.rate_hz);
    live.started = true;
    const MonitorOutput& out = live.output;
    if (out.summary) {
      std::cout << "  monitor: " << counters_text(*out.summary) << "; " << out.transitions.size()
                << " alarm transitions\n";
      if (out.summary->contains("walls") && (*out.summary)["walls"].is_array()) {
        std::string walls;
        for (const nlohmann::json& w : (*out.summary)["walls"]) {
          walls += (walls.empty() ? "" : ", ") + w.value("name", std::string("?")) + " " +
                   w.value("max_alarm_level", std::string("?"));
        }
        std::cout << "  walls (highest level): " << walls << " (" << out.other_walls_transitions
                  << " transitions of the walls other than \"wall\")\n";
      }
      const std::int64_t received = counter(out.summary, "samples_received");
      if (received >= 0 && static_cast<std::size_t>(received) != outcome.samples_sent) {
        std::cout << "  note: the monitor received " << received << " of the " << outcome.samples_sent
                  << " samples sent: datagrams were lost (a busy machine; a lower --speed helps), and where the "
                     "monitor bridged the gap its input differs from the offline one\n";
      }
    } else {
      std::cout << "  monitor: no summary (" << monitor.exit_text() << "); its messages:\n" << file_text(err_path);
    }
    if (!live.clean) std::cout << "  the monitor did not stop cleanly (" << monitor.exit_text() << ")\n";
    return live;
  }

  // The samples: the suite record scaled to the PGA, at the demo's rate, exactly as `rockwatch replay` makes them.
  ReplayStream suite_stream(char component) const { return suite_stream(component, q_.pga_g); }
  ReplayStream suite_stream(char component, double pga_g) const {
    InputRequest s;
    SuiteSelection suite;
    suite.dir = q_.suite_dir;
    suite.set = q_.set;
    suite.component = component;
    s.record.record_path = records::suite_set_path(q_.suite_dir, q_.set);
    s.record.suite = suite;
    s.record.channel = std::string(1, component);
    s.record.channel_is_component = true;
    s.record.read_options.channel = s.record.channel;
    s.record.read_options.g_mps2 = s.g_mps2;
    s.scale_pga_g = pga_g;
    const InputMotion input = prepare_input(s);
    return make_replay_stream(input.motion, q_.rate_hz, SensorModel{});
  }

 private:
  static void write_samples_file(const std::string& path, const ReplayStream& stream) {
    std::ofstream out(path, std::ios::binary);
    write_samples_csv(out, stream, stream.size());
  }

  const DemoRequest& q_;
  const MonitorLocation& monitor_;
  const WorkDir& work_;
  const SignalInterrupt& interrupt_;
};

// `rockwatch dashboard` as a child process (this executable: a command never includes another command's code), on
// the demo's LCM URL, with the demo monitor's wall (paper wall, kappa 2: the dashboard's defaults).
class DemoDashboard {
  static std::vector<std::string> dashboard_arguments(const DemoRequest& q) {
    std::vector<std::string> a{"dashboard", "--http", q.dashboard_http, "--lcm-url", q.lcm_url};
    if (q.wall_file) a.insert(a.end(), {"--wall-file", *q.wall_file});
    return a;
  }

 public:
  DemoDashboard(const DemoRequest& q, const WorkDir& work) : out_(work.file("dashboard.out")) {
    std::error_code ec;
    const std::string self = std::filesystem::read_symlink("/proc/self/exe", ec).string();
    if (ec) throw std::runtime_error("cannot find this executable to start the dashboard: " + ec.message());
    process_ = std::make_unique<MonitorProcess>(
        self, dashboard_arguments(q), out_, work.file("dashboard.err"));
    err_ = work.file("dashboard.err");
  }

  // Waits until it prints its URL; throws UsageError with its message when it ends first (address in use...).
  std::string wait_for_url() {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    constexpr const char* kServing = "serving on ";
    while (std::chrono::steady_clock::now() < deadline) {
      const std::string text = file_text(out_);
      const std::size_t at = text.find(kServing);
      if (at != std::string::npos && text.find('\n', at) != std::string::npos) {
        const std::size_t start = at + std::strlen(kServing);
        return text.substr(start, text.find('\n', at) - start);
      }
      if (!process_->running()) {
        std::string message = file_text(err_);
        const std::string prefix = "rockwatch dashboard: error: ";
        if (message.rfind(prefix, 0) == 0) message = message.substr(prefix.size());
        while (!message.empty() && message.back() == '\n') message.pop_back();
        throw UsageError("--dashboard: the dashboard did not start (" + process_->exit_text() + "): " + message);
      }
      usleep(20000);
    }
    throw std::runtime_error("the dashboard did not print its URL within 10 s");
  }

  void stop() { process_->stop(kMonitorStopTimeout_s); }

 private:
  std::string out_, err_;
  std::unique_ptr<MonitorProcess> process_;
};

int run(const DemoRequest& q) {
  const MonitorLocation monitor = find_monitor(q.monitor);
  const core::WallParameters wall = q.wall;
  std::cout << "rockwatch demo: " << (q.wall_file ? "the wall of " + *q.wall_file : std::string("the paper's wall"))
            << " (b " << number_text(wall.b_m) << " m, h "
            << number_text(wall.h1_m + wall.h2_m) << " m), watched live by rockwatch-monitor over LCM\n"
            << "  each record is replayed to a fresh monitor as a sensor would send it, then compared with the\n"
               "  offline simulation of the same samples\n"
            << "  suite: " << q.suite_dir << " (" << q.suite_found_by << "), set " << q.set << ", PGA "
            << number_text(q.pga_g) << " g; " << number_text(q.rate_hz) << " Hz, "
            << (q.speed == 1.0 ? std::string("real time") : "speed " + number_text(q.speed)) << "\n"
            << std::flush;

  const MulticastProbe probe = probe_multicast(q.lcm_url, 1000);
  if (!probe.ok) {
    std::cout << std::flush;
    std::cerr << kErrors.prefix << multicast_help(q.lcm_url, probe);
    return kExitUsageError;
  }
  std::cout << "  LCM: " << q.lcm_url << ", multicast on this machine works (probe back in "
            << decimals(probe.round_trip_ms, 2) << " ms)\n"
            << "  monitor: " << monitor.path << " (" << monitor.found_by << ")\n"
            << std::flush;

  const WorkDir work(q.out_dir);
  std::unique_ptr<DemoDashboard> dashboard;
  if (q.dashboard) {
    dashboard = std::make_unique<DemoDashboard>(q, work);
    const std::string url = dashboard->wait_for_url();
    std::cout << "  dashboard: " << url << "  <- open it in a browser to watch the wall live\n" << std::flush;
  }
  const SignalInterrupt interrupt;
  Demo demo(q, monitor, work, interrupt);
  std::vector<CaseResult> results;
  int index = 0;
  constexpr int kCases = 4;
  for (const char component : kComponents) {
    results.push_back(demo.run_case(component, ++index, kCases));
    if (interrupt.interrupted()) {
      std::cout << "\ninterrupted\n" << std::flush;
      return kExitInterrupted;
    }
  }
  // The survivor's record again, on an instrumented wall whose restitution the nominal model gets wrong.
  results.push_back(demo.run_instrumented_case(kComponents[1], ++index, kCases));
  if (interrupt.interrupted()) {
    std::cout << "\ninterrupted\n" << std::flush;
    return kExitInterrupted;
  }
  // Component Y again, weaker, on a wall thinner than its drawings: the capacity the monitor must learn.
  results.push_back(demo.run_thinner_wall_case(kComponents[0], ++index, kCases));
  if (interrupt.interrupted()) {
    std::cout << "\ninterrupted\n" << std::flush;
    return kExitInterrupted;
  }

  bool all = true;
  std::cout << "\n== result\n";
  for (const CaseResult& r : results) {
    all = all && r.match;
    std::cout << "  " << r.title << ": offline " << r.verdict << "; monitor "
              << (r.match ? "matches" : "DOES NOT match") << " (highest level " << r.monitor_max_level << ")\n";
  }
  if (all) {
    std::cout << "The live monitor raised the same alarms, at the same samples (within one), as the offline "
                 "simulation of the same input (for the instrumented wall: of the same input and sensors).\n";
  } else {
    std::cout << "The live monitor's alarms differ from the offline simulation (see above";
    if (q.out_dir) std::cout << "; files in " << *q.out_dir;
    std::cout << ").\n";
  }
  if (dashboard) {
    if (q.dashboard_hold_s > 0.0) {
      std::cout << "  dashboard: serving " << number_text(q.dashboard_hold_s) << " s more (Ctrl-C ends it)\n"
                << std::flush;
      const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(q.dashboard_hold_s);
      while (!interrupt.interrupted() && std::chrono::steady_clock::now() < until) usleep(50000);
    }
    dashboard->stop();
  }
  const int status = finish_stdout(kErrors);
  if (status != kExitOk) return status;
  return all ? kExitOk : kExitInternalError;
}

}  // namespace

int demo_main(int argc, const char* const* argv) {
  return run_command(kErrors, [&] {
    const DemoParse parsed = parse_demo_arguments(argc, argv);
    if (!parsed.request) return print_help(parsed.help_text);
    return run(*parsed.request);
  });
}

}  // namespace rockwatch::cli
