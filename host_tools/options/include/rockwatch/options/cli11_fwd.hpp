// The CLI11 classes the option headers name, declared and not defined: a header that passes CLI::App by reference
// includes this, and only the files that build or parse a command line include <CLI/CLI.hpp>. Including CLI11 costs a
// translation unit about 7 s of g++ at -O3 and 9 s under the sanitizers even when nothing of it is used (each file
// constructs its own copy of CLI11's validator objects); CMakeLists.txt compiles the files that do include it as one unit
// per library (docs/BENCHMARKS.md "The test loop").
#pragma once

namespace CLI {
class App;
class Option;
}  // namespace CLI
