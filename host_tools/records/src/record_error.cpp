// RecordError: "PATH:LINE: message", the form compilers use, so editors can jump to the defect.
#include "rockwatch/records/record_error.hpp"

#include <string>
#include <utility>

namespace rockwatch::records {

namespace {

std::string located_message(const std::string& file_path, int line, const std::string& message) {
  std::string text = file_path;
  if (line > 0) {
    text += ':';
    text += std::to_string(line);
  }
  text += ": ";
  text += message;
  return text;
}

}  // namespace

RecordError::RecordError(std::string file_path, int line, const std::string& message)
    : std::runtime_error(located_message(file_path, line, message)), path_(std::move(file_path)), line_(line) {}

}  // namespace rockwatch::records
