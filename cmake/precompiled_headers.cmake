# Precompiled headers (docs/BENCHMARKS.md, "The test loop"; issue 42: the fresh-clone CI within 24 min).
# A test file spends about a third of its compile time parsing the standard library, nlohmann/json and Eigen before
# its own code (g++ -ftime-report: 41 % of test_study_alarm.cpp's wall time is "phase parsing"); a precompiled header
# parses them once per target. Measured on test_study_alarm.cpp: 12.8 s -> 10.4 s; building one costs about 6 s, so only
# the targets of four files or more (the test suites, rockwatch_cli's 20 unity files) have one.
# Only what is parsed everywhere goes in: the standard headers, nlohmann/json and Eigen/Core. Not CppUTest
# (TestHarness.h defines `new` as a macro, which must come after every header a test file includes) and not CLI11
# (it defines validator objects that each translation unit would then construct).
# -DROCKWATCH_PCH=OFF compiles without them (and so checks that every file includes what it uses, with
# -DROCKWATCH_UNITY_BUILD=OFF).
option(ROCKWATCH_PCH "Precompile the standard, nlohmann/json and Eigen headers for the host libraries and the test suites" ON)

set(ROCKWATCH_PCH_STD_HEADERS
  <algorithm> <array> <atomic> <chrono> <cmath> <cstddef> <cstdint> <cstdio> <cstdlib> <cstring> <filesystem>
  <fstream> <functional> <iostream> <limits> <map> <memory> <optional> <ostream> <set> <sstream> <string>
  <system_error> <utility> <vector>)

# rockwatch_precompile(TARGET [EIGEN]): TARGET's files start from its own precompiled headers (with EIGEN: and
# Eigen/Core). Each target builds its own: g++ accepts a precompiled header built with other code-generation options
# (-fno-strict-aliasing, for one) without a word and compiles the whole file with the header's, so sharing one between
# targets of different flags (CMake's REUSE_FROM) silently changes the code (test_firmware's bit-exact checks failed).
function(rockwatch_precompile target)
  if(NOT ROCKWATCH_PCH)
    return()
  endif()
  cmake_parse_arguments(ARG "EIGEN" "" "" ${ARGN})
  set(_headers ${ROCKWATCH_PCH_STD_HEADERS} <nlohmann/json.hpp>)
  if(ARG_EIGEN)
    list(APPEND _headers <Eigen/Core>)
    target_link_libraries(${target} PRIVATE Eigen3::Eigen)  # its include path (a suite of records needs none else)
  endif()
  target_precompile_headers(${target} PRIVATE ${_headers})
endfunction()
