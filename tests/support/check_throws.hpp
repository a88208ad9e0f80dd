// Asserts that `fn` throws an exception of type E (and not something else, nor nothing).
#pragma once

#include <CppUTest/TestHarness.h>

namespace rockwatch::test {

template <typename E, typename Fn>
void check_throws(Fn fn, const char* expectation) {
  bool thrown = false;
  try {
    fn();
  } catch (const E&) {
    thrown = true;
  }
  CHECK_TEXT(thrown, expectation);
}

}  // namespace rockwatch::test
