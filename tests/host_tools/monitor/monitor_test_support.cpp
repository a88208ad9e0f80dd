#include "monitor_test_support.hpp"

#include <unistd.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "monitor_config.hpp"  // fnv1a64

namespace rockwatch::test {

ProcessResult run_monitor(const std::vector<std::string>& arguments) {
  return run_program(ROCKWATCH_MONITOR_PATH, arguments);
}

pid_t spawn_monitor(const std::vector<std::string>& arguments, const std::string& out_path,
                    const std::string& err_path) {
  return spawn_program(ROCKWATCH_MONITOR_PATH, arguments, out_path, err_path);
}

std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw std::runtime_error("cannot write " + path);
}

std::vector<nlohmann::json> json_lines(const std::string& text) {
  std::vector<nlohmann::json> lines;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    try {
      lines.push_back(nlohmann::json::parse(line));
    } catch (const nlohmann::json::parse_error&) {
      throw std::runtime_error("not a JSON line: " + line);
    }
  }
  return lines;
}

std::string monitor_data_path(const std::string& name) { return std::string(ROCKWATCH_TEST_DATA_DIR) + "/monitor/" + name; }

namespace {

template <typename Message>
Message decode_event(const lcm::LogEvent& e) {
  Message m;
  if (m.decode(e.data, 0, e.datalen) != e.datalen) {
    throw std::runtime_error("output log event " + std::to_string(e.eventnum) + " on " + e.channel +
                             " does not decode as its type");
  }
  return m;
}

}  // namespace

OutputLog read_output_log(const std::string& path) {
  lcm::LogFile log(path, "r");
  if (!log.good()) throw std::runtime_error("cannot open " + path);
  OutputLog out;
  out.state_digest = 14695981039346656037ull;
  for (const lcm::LogEvent* e = log.readNextEvent(); e != nullptr; e = log.readNextEvent()) {
    ++out.events;
    if (e->channel == "ROCKWATCH_WALL_STATE") {
      out.states.push_back({{e->timestamp}, decode_event<rockwatch::wall_state_t>(*e)});
      std::string bytes(reinterpret_cast<const char*>(&e->timestamp), sizeof e->timestamp);
      bytes.append(static_cast<const char*>(e->data), static_cast<std::size_t>(e->datalen));
      out.state_digest = monitor::fnv1a64(bytes, out.state_digest);
    } else if (e->channel == "ROCKWATCH_ALARM") {
      out.alarms.push_back({{e->timestamp}, decode_event<rockwatch::alarm_event_t>(*e)});
    } else if (e->channel == "ROCKWATCH_STATUS") {
      out.statuses.push_back({{e->timestamp}, decode_event<rockwatch::monitor_status_t>(*e)});
    } else {
      out.other_channels.push_back(e->channel);
    }
  }
  return out;
}

std::string unique_channel(const std::string& base) { return base + "_" + std::to_string(getpid()); }

}  // namespace rockwatch::test
