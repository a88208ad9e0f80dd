// The suite directory's manifest.json: which file holds which set. Only "format", "sets", "set" and "file" are
// read; the rest of the manifest is for people.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <system_error>
#include <vector>

#include "rockwatch/records/record_error.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "text_scan.hpp"

namespace rockwatch::records {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

// A manifest lists a few dozen sets; anything far larger is not one, and is refused before it is parsed.
constexpr std::uintmax_t kMaxManifestBytes = std::uintmax_t{16} * 1024U * 1024U;

struct SetEntry {
  int set = 0;
  std::string file;
};

std::string manifest_path(const std::string& dir) { return (fs::path(dir) / kSuiteManifestName).string(); }

int line_of_byte(const std::string& content, std::size_t byte) {
  const std::size_t end = std::min(byte, content.size());
  return 1 + static_cast<int>(std::count(content.begin(), content.begin() + static_cast<std::ptrdiff_t>(end), '\n'));
}

// nlohmann's message without its "[json.exception.parse_error.101] " tag, printable and bounded: it quotes what it
// last read, which may be anything.
std::string parse_problem(const std::string& what) {
  constexpr std::size_t kMaxShown = 200;
  const std::size_t tag_end = what.rfind("] ", what.find("parse error"));
  std::string text = tag_end == std::string::npos ? what : what.substr(tag_end + 2);
  if (text.size() > kMaxShown) text = text.substr(0, kMaxShown) + "...";
  for (char& c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (u < 0x20 || u >= 0x7F) c = '?';
  }
  return text;
}

std::string entry_name(std::size_t index) { return "sets[" + std::to_string(index) + "]"; }

// Set files live in the suite directory (or below it): a manifest must not send a reader elsewhere.
void check_relative(const std::string& path, std::size_t index, const std::string& file) {
  const fs::path relative(file);
  if (file.empty()) {
    throw RecordError(path, 0, entry_name(index) + ": empty \"file\": expected a file name such as \"set01.txt\"");
  }
  if (relative.is_absolute() || relative.has_root_name() || relative.has_root_directory()) {
    throw RecordError(path, 0,
                      entry_name(index) + ": \"file\" " + detail::shown(file) +
                          " is an absolute path: expected a file name inside the suite directory");
  }
  for (const fs::path& part : relative) {
    if (part == "..") {
      throw RecordError(path, 0,
                        entry_name(index) + ": \"file\" " + detail::shown(file) +
                            " leaves the suite directory ('..'): expected a file name inside it");
    }
  }
}

std::vector<SetEntry> read_manifest(const std::string& dir) {
  const std::string path = manifest_path(dir);
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    throw RecordError(path, 0,
                      "no suite manifest: expected " + std::string(kSuiteManifestName) + " in " + detail::shown(dir) +
                          " (a directory written by rockwatch generate)");
  }
  const std::uintmax_t size = fs::is_regular_file(path, ec) ? fs::file_size(path, ec) : 0;
  if (!ec && size > kMaxManifestBytes) {
    throw RecordError(path, 0,
                      "manifest of " + std::to_string(size) + " bytes: expected a suite manifest of at most " +
                          std::to_string(kMaxManifestBytes) + " bytes");
  }
  const std::string content = detail::read_whole_file(path);
  json manifest;
  try {
    manifest = json::parse(content);
  } catch (const json::parse_error& error) {
    throw RecordError(
        path, line_of_byte(content, error.byte == 0 ? 0 : error.byte - 1),
        "malformed JSON (" + parse_problem(error.what()) + "): expected the manifest written by rockwatch generate");
  } catch (const json::exception& error) {
    // nlohmann reports a number beyond double ("1e400") as out_of_range, not as a parse_error.
    throw RecordError(path, 0,
                      "malformed JSON (" + parse_problem(error.what()) +
                          "): expected the manifest written by rockwatch generate");
  }
  if (!manifest.is_object()) {
    throw RecordError(path, 0, "expected a JSON object with \"format\" and \"sets\"");
  }
  const auto format = manifest.find("format");
  if (format == manifest.end() || !format->is_string() || format->get<std::string>() != kSuiteManifestFormat) {
    throw RecordError(path, 0,
                      "\"format\": expected \"" + std::string(kSuiteManifestFormat) + "\", found " +
                          (format == manifest.end() ? std::string("none") : detail::shown(format->dump())));
  }
  const auto version = manifest.find("version");
  if (version != manifest.end() && !(version->is_number_integer() && version->get<std::int64_t>() == 1)) {
    throw RecordError(
        path, 0,
        "\"version\": " + detail::shown(version->dump()) + ": expected 1 (written by another rockwatch release?)");
  }
  const auto sets = manifest.find("sets");
  if (sets == manifest.end() || !sets->is_array()) {
    throw RecordError(path, 0, "\"sets\": expected an array of {\"set\": N, \"file\": \"...\"}");
  }
  std::vector<SetEntry> entries;
  for (std::size_t index = 0; index < sets->size(); ++index) {
    const json& item = (*sets)[index];
    if (!item.is_object()) {
      throw RecordError(path, 0, entry_name(index) + ": expected an object {\"set\": N, \"file\": \"...\"}");
    }
    const auto set = item.find("set");
    if (set == item.end() || !set->is_number_integer() || set->get<std::int64_t>() < 1 ||
        set->get<std::int64_t>() > std::numeric_limits<int>::max()) {
      throw RecordError(path, 0,
                        entry_name(index) + ": \"set\": expected a whole number of 1 or more, found " +
                            (set == item.end() ? std::string("none") : detail::shown(set->dump())));
    }
    const auto file = item.find("file");
    if (file == item.end() || !file->is_string()) {
      throw RecordError(path, 0,
                        entry_name(index) + ": \"file\": expected the set file's name as a string, found " +
                            (file == item.end() ? std::string("none") : detail::shown(file->dump())));
    }
    SetEntry entry{static_cast<int>(set->get<std::int64_t>()), file->get<std::string>()};
    check_relative(path, index, entry.file);
    const bool repeated =
        std::any_of(entries.begin(), entries.end(), [&entry](const SetEntry& other) { return other.set == entry.set; });
    if (repeated) {
      throw RecordError(
          path, 0,
          entry_name(index) + ": set " + std::to_string(entry.set) + " is listed twice: expected each set once");
    }
    entries.push_back(std::move(entry));
  }
  return entries;
}

// "1-11" or "1-3, 5, 8-9": the sets a manifest offers, short enough for one message.
std::string set_ranges(std::vector<int> sets) {
  std::sort(sets.begin(), sets.end());
  std::string text;
  for (std::size_t i = 0; i < sets.size();) {
    std::size_t j = i;
    while (j + 1 < sets.size() && sets[j + 1] == sets[j] + 1) ++j;
    if (!text.empty()) text += ", ";
    text += std::to_string(sets[i]);
    if (j > i) text += "-" + std::to_string(sets[j]);
    i = j + 1;
  }
  return text;
}

}  // namespace

std::vector<int> suite_sets(const std::string& dir) {
  std::vector<int> sets;
  for (const SetEntry& entry : read_manifest(dir)) sets.push_back(entry.set);
  return sets;
}

std::string suite_set_path(const std::string& dir, int set) {
  const std::vector<SetEntry> entries = read_manifest(dir);
  for (const SetEntry& entry : entries) {
    if (entry.set == set) return (fs::path(dir) / entry.file).string();
  }
  std::vector<int> sets;
  for (const SetEntry& entry : entries) sets.push_back(entry.set);
  throw RecordError(manifest_path(dir), 0,
                    "no set " + std::to_string(set) + " in the manifest: " +
                        (sets.empty() ? std::string("it lists no sets") : "it has sets " + set_ranges(sets)));
}

}  // namespace rockwatch::records
