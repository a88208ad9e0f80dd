#include "common/process/command_runner.hpp"

#include <cerrno>
#include <cstring>
#include <exception>
#include <iostream>
#include <new>

#include "common/process/commands.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"
#include "rockwatch/records/record_error.hpp"
#include "rockwatch/sim/analysis.hpp"
#include "rockwatch/sim/measure_error.hpp"

namespace rockwatch::cli {

int fail(const CommandErrors& errors, const std::string& message, int status) {
  std::cerr << errors.prefix << message << '\n';
  return status;
}

int run_command(const CommandErrors& errors, const std::function<int()>& body) {
  try {
    return body();
  } catch (const UsageError& e) {
    return fail(errors, e.what(), kExitUsageError);
  } catch (const records::RecordError& e) {
    return fail(errors, e.what(), kExitUsageError);
  } catch (const sim::AnalysisError& e) {
    return fail(errors, std::string("analysis refused the input: ") + e.what(), kExitUsageError);
  } catch (const sim::MeasureError& e) {
    return fail(errors, std::string("the record cannot be measured: ") + e.what(), kExitUsageError);
  } catch (const std::bad_alloc&) {
    return fail(errors, errors.out_of_memory, kExitInternalError);
  } catch (const std::exception& e) {
    return fail(errors, std::string("internal error: ") + e.what(), kExitInternalError);
  }
}

int print_help(const std::string& help_text) {
  std::cout << help_text;
  return kExitOk;
}

int finish_stdout(const CommandErrors& errors) {
  std::cout.flush();
  if (!std::cout) return fail(errors, "cannot write the result to standard output", kExitUsageError);
  return kExitOk;
}

std::string system_reason() {
  const int code = errno;
  return code != 0 ? std::string(": ") + std::strerror(code) : std::string();
}

}  // namespace rockwatch::cli
