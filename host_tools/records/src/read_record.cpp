// Format detection and dispatch: the content decides, not the extension, because records are renamed freely
// (".txt" AT2 downloads, ".AT2" files converted to columns, miniSEED saved without ".mseed").
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <ios>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

#include "rockwatch/records/record.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "text_scan.hpp"

namespace rockwatch::records {

namespace {

// ESM headers run to about 64 lines; ITACA's to 10.
constexpr std::size_t kEsmSniffLines = 80;
constexpr std::size_t kItacaSniffLines = 20;

// Reads at most the first `count` lines and at most 64 KiB, so sniffing a large file without newlines stays cheap.
std::vector<std::string> first_lines(const std::string& path, std::size_t count = 4) {
  constexpr std::size_t kMaxBytes = 65536;
  std::vector<std::string> lines;
  std::ifstream in(path, std::ios::binary);
  if (!in) return lines;
  std::string head(kMaxBytes, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  for (const std::string_view line : detail::split_lines(head)) {
    if (lines.size() == count) break;
    lines.emplace_back(line);
  }
  return lines;
}

bool mentions_npts_and_dt(std::string_view line) {
  const std::string upper = detail::to_upper(line);
  return upper.find("NPTS") != std::string::npos && upper.find("DT") != std::string::npos;
}

// The key of a `KEY: value` / `key : value` header line, trimmed; empty when the line has no ':'.
std::string_view key_before_colon(std::string_view line) {
  const std::size_t colon = line.find(':');
  if (colon == std::string_view::npos) return {};
  return detail::trim(line.substr(0, colon));
}

}  // namespace

bool looks_like_esm_ascii(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  // Two of the keys every ESM header has, one of them the sampling (so a file missing the other is still read as
  // ESM and told what is missing, instead of being misread as columns).
  bool sampling = false;
  int keys = 0;
  for (const std::string& line : first_lines(path, kEsmSniffLines)) {
    const std::string_view key = key_before_colon(line);
    // ESM writes "KEY:" at the start of the line, with no blank before ':'.
    if (key.empty() || line.compare(0, key.size(), key) != 0 || line.size() <= key.size() || line[key.size()] != ':') {
      continue;
    }
    if (key == "SAMPLING_INTERVAL_S" || key == "NDATA") sampling = true;
    for (const std::string_view known : {"EVENT_NAME", "EVENT_ID", "NETWORK", "STATION_CODE", "STREAM", "UNITS",
                                         "NDATA", "SAMPLING_INTERVAL_S", "DATA_TYPE"}) {
      if (key == known) ++keys;
    }
  }
  return sampling && keys >= 2;
}

bool looks_like_itaca_cor_acc(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return false;
  for (const std::string& line : first_lines(path, kItacaSniffLines)) {
    const std::string key = detail::to_upper(key_before_colon(line));
    if (key == "TIME INCREMENT (S)" || key == "NUMBER OF DATA") return true;
  }
  return false;
}

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
  // Binary first: a miniSEED header cannot pass for text, while the text sniffers only look at lines.
  if (looks_like_miniseed(path)) return read_miniseed(path, options);
  if (looks_like_suite_record(path)) return read_suite_component(path, options);
  if (looks_like_esm_ascii(path)) return read_esm_ascii(path, options);
  if (looks_like_itaca_cor_acc(path)) return read_itaca_cor_acc(path, options);
  if (looks_like_peer_at2(path)) return read_peer_at2(path, options);
  return read_plain_text(path, options);
}

}  // namespace rockwatch::records
