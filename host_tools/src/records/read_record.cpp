// Format detection and dispatch: the content decides, not the extension, because records are renamed freely
// (".txt" AT2 downloads, ".AT2" files converted to columns).
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <ios>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "rockwatch/records/record.hpp"
#include "text_scan.hpp"

namespace rockwatch::records {

namespace {

// Reads at most the first four lines and at most 64 KiB, so sniffing a large file without newlines stays cheap.
std::vector<std::string> first_lines(const std::string& path) {
  constexpr std::size_t kLines = 4;
  constexpr std::size_t kMaxBytes = 65536;
  std::vector<std::string> lines;
  std::ifstream in(path, std::ios::binary);
  if (!in) return lines;
  std::string head(kMaxBytes, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  for (const std::string_view line : detail::split_lines(head)) {
    if (lines.size() == kLines) break;
    lines.emplace_back(line);
  }
  return lines;
}

bool mentions_npts_and_dt(std::string_view line) {
  const std::string upper = detail::to_upper(line);
  return upper.find("NPTS") != std::string::npos && upper.find("DT") != std::string::npos;
}

}  // namespace

bool looks_like_peer_at2(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  const std::vector<std::string> lines = first_lines(path);
  if (!lines.empty() && detail::to_upper(detail::trim(lines[0])).rfind("PEER NGA", 0) == 0) return true;
  if (lines.size() >= 3) {
    const std::string units = detail::to_upper(lines[2]);
    if (units.find("TIME SERIES IN UNITS OF") != std::string::npos || units.find("UNITS OF G") != std::string::npos) {
      return true;
    }
  }
  // Line 4 naming NPTS and DT is the AT2 signature in all three spellings; a '#' line is a plain-text comment.
  if (lines.size() >= 4) {
    const std::string_view fourth = detail::trim(lines[3]);
    if (!fourth.empty() && fourth.front() != '#' && mentions_npts_and_dt(fourth)) return true;
  }
  return false;
}

Record read_record(const std::string& path, const ReadOptions& options) {
  if (looks_like_peer_at2(path)) return read_peer_at2(path, options);
  return read_plain_text(path, options);
}

}  // namespace rockwatch::records
