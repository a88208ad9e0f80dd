#include "dashboard/dashboard_channels.hpp"

#include <string>

#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

namespace {

constexpr std::size_t kMaxChannelBaseLength = 40;

bool is_base_char(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
}

constexpr ChannelKind kAllKinds[] = {ChannelKind::state,  ChannelKind::alarm,    ChannelKind::status,
                                     ChannelKind::sensor, ChannelKind::estimate, ChannelKind::forecast};

}  // namespace

const std::string& DashboardChannels::base(ChannelKind kind) const {
  switch (kind) {
    case ChannelKind::state: return state;
    case ChannelKind::alarm: return alarm;
    case ChannelKind::status: return status;
    case ChannelKind::sensor: return sensor;
    case ChannelKind::estimate: return estimate;
    case ChannelKind::forecast: return forecast;
  }
  return state;
}

void check_channel_base(const std::string& option, const std::string& base) {
  bool ok = !base.empty() && base.size() <= kMaxChannelBaseLength;
  for (const char c : base) ok = ok && is_base_char(c);
  if (!ok) {
    throw UsageError(option + " must be a channel name of 1 to " + std::to_string(kMaxChannelBaseLength) +
                     " characters A-Z, a-z, 0-9 and _ (got " + options::quoted(base) + ")");
  }
}

bool valid_wall_name(const std::string& name) {
  if (name.empty() || name.size() > kMaxWallNameLength) return false;
  for (const char c : name) {
    if (!is_base_char(c) && c != '-') return false;
  }
  return true;
}

std::optional<ChannelMatch> match_channel(const DashboardChannels& channels, const std::string& channel) {
  if (channel.size() > kMaxChannelLength) return std::nullopt;
  std::optional<ChannelMatch> best;
  std::size_t best_length = 0;
  for (const ChannelKind kind : kAllKinds) {
    const std::string& base = channels.base(kind);
    if (channel == base) return ChannelMatch{kind, kDefaultWallName};  // an exact name is never a suffixed one
    if (channel.size() > base.size() + 1 && channel.compare(0, base.size(), base) == 0 &&
        channel[base.size()] == '_' && base.size() > best_length) {
      const std::string wall = channel.substr(base.size() + 1);
      if (valid_wall_name(wall)) {
        best = ChannelMatch{kind, wall};
        best_length = base.size();
      }
    }
  }
  return best;
}

std::string subscription_regex(const std::string& base) { return base + "(_[A-Za-z0-9_-]+)?"; }

const char* channel_kind_name(ChannelKind kind) {
  switch (kind) {
    case ChannelKind::state: return "state";
    case ChannelKind::alarm: return "alarm";
    case ChannelKind::status: return "status";
    case ChannelKind::sensor: return "sensor";
    case ChannelKind::estimate: return "estimate";
    case ChannelKind::forecast: return "forecast";
  }
  return "?";
}

}  // namespace rockwatch::cli
