// A test that cannot run here because a tool or a service is missing (chromium, QEMU and the ARM toolchain, Python
// with matplotlib, LCM's UDP multicast on loopback, MPI ...): outside CI it skips, saying why; under CI=true (CI sets
// it; issue 42) it fails, naming what is missing, so that a green CI run is one in which everything ran. The
// scripts' counterpart is tests/support/no_skip_in_ci.sh (exit 77 turned into a failure under CI=true).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

// Utest.h only, not TestHarness.h: this header may come before the standard headers of a file, which CppUTest's
// operator new macros (TestHarness.h) would break.
#include <CppUTest/Utest.h>

namespace rockwatch::test {

// CI=true in the environment (GitHub Actions, GitLab and the project's .ci/run set it).
inline bool under_ci() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::strcmp(ci, "true") == 0;
}

// Call where the current test would return early because `missing` is not there: fails the test under CI=true,
// otherwise prints "SKIPPED: <test>: missing" and returns true (then return from the test).
inline bool skip_or_fail_in_ci(const std::string& missing) {
  const UtestShell* t = UtestShell::getCurrent();
  const std::string name = t != nullptr ? t->getGroup().asCharString() + std::string(".") + t->getName().asCharString()
                                        : std::string("this test");
  if (under_ci()) {
    const std::string text = "not run under CI=true (CI must run every test): " + missing;
    UtestShell::getCurrent()->fail(text.c_str(), __FILE__, __LINE__);
  }
  std::printf("\nSKIPPED: %s: %s\n", name.c_str(), missing.c_str());
  return true;
}

}  // namespace rockwatch::test
