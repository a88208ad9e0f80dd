// A mistake the user can fix (an option value, a combination of files). Commands print it as
// "rockwatch COMMAND: error: MESSAGE" and exit with kExitUsageError.
#pragma once

#include <stdexcept>

namespace rockwatch::options {

class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace rockwatch::options
