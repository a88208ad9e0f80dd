// Shared by the record-reader suites: catching a reader's RecordError as data, checking where it points, and a
// scratch directory for hand-made files.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <system_error>
#include <vector>

#include "rockwatch/records/record.hpp"
#include "rockwatch/records/record_error.hpp"

// After the standard headers: CppUTest's leak-detector macros redefine new/malloc.
#include <CppUTest/TestHarness.h>

namespace rockwatch::test {

// The RecordError message and line of `action`, or a marker that fails every STRCMP_CONTAINS when nothing (or
// something else) was thrown.
struct Failure {
  std::string message;
  int line = -1;
};

inline Failure failure_of(const std::function<void()>& action) {
  try {
    action();
  } catch (const records::RecordError& error) {
    return {error.what(), error.line()};
  } catch (const std::exception& other) {
    return {std::string("<unexpected exception> ") + other.what(), -1};
  }
  return {"<no exception thrown>", -1};
}

// Checks that a rejection of file `name` names it with its line (":N:", or no line when line == 0) and contains
// every fragment.
inline void check_rejection(const Failure& f, const std::string& name, int line,
                            const std::vector<std::string>& fragments) {
  const std::string located = line > 0 ? name + ":" + std::to_string(line) + ": " : name + ": ";
  STRCMP_CONTAINS(located.c_str(), f.message.c_str());
  LONGS_EQUAL(line, f.line);
  for (const std::string& fragment : fragments) STRCMP_CONTAINS(fragment.c_str(), f.message.c_str());
}

// True when one of the record's notes contains every fragment.
inline bool has_note_with(const records::Record& record, const std::vector<std::string>& fragments) {
  return std::any_of(record.notes.begin(), record.notes.end(), [&fragments](const std::string& note) {
    return std::all_of(fragments.begin(), fragments.end(),
                       [&note](const std::string& f) { return note.find(f) != std::string::npos; });
  });
}

// A fresh directory under the system's temporary directory, named prefix_XXXXXX.
inline std::filesystem::path make_scratch_dir(const std::string& prefix) {
  std::string pattern = (std::filesystem::temp_directory_path() / (prefix + "_XXXXXX")).string();
  const char* made = mkdtemp(pattern.data());
  CHECK_TRUE_TEXT(made != nullptr, "mkdtemp failed");
  return pattern;
}

inline void remove_scratch_dir(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
}

// Writes `content` to dir/name (creating subdirectories) in binary, so "\r\n" and a missing final newline reach
// the reader as written; returns the path.
inline std::string write_test_file(const std::filesystem::path& dir, const std::string& name,
                                   const std::string& content) {
  const std::filesystem::path path = dir / name;
  std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary);
  out << content;
  return path.string();
}

// Base of the hand-made-file test groups (TEST_GROUP_BASE(Group, rockwatch::test::HandMadeFileTest)): a scratch
// directory per test, files written into it, and rejections checked through read_record (so format detection is
// part of every case).
class HandMadeFileTest : public Utest {
 public:
  void setup() override { dir = make_scratch_dir("rockwatch_records"); }
  void teardown() override { remove_scratch_dir(dir); }

 protected:
  std::string write(const std::string& name, const std::string& content) { return write_test_file(dir, name, content); }

  void expect_rejected(const std::string& name, const std::string& content, int line,
                       const std::vector<std::string>& fragments, const records::ReadOptions& options = {}) {
    const std::string path = write(name, content);
    check_rejection(failure_of([&] { records::read_record(path, options); }), name, line, fragments);
  }

  std::filesystem::path dir;
};

}  // namespace rockwatch::test
