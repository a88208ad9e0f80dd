// Where `rockwatch study` (and `rockwatch demo`) find the shipped suite (sim/suites/npr9998-2015) when no --suite or --records is given,
// so the paper's study runs with no path at all: from the build tree, from an installation, or wherever
// $ROCKWATCH_SUITE_DIR points.
#pragma once

#include <string>

namespace rockwatch::cli {

inline constexpr const char* kShippedSuiteName = "npr9998-2015";
inline constexpr const char* kSuiteDirVariable = "ROCKWATCH_SUITE_DIR";

struct SuiteLocation {
  std::string dir;
  std::string found_by;  // "$ROCKWATCH_SUITE_DIR", "the installation (<bin>/../share/rockwatch/suites)", ...
};

// $ROCKWATCH_SUITE_DIR when set (an error when it holds no suite: the user asked for it), else
// <directory of the executable>/../share/rockwatch/suites/npr9998-2015, else the source tree's copy the tool was
// built from. A candidate counts when it has a manifest.json. Throws UsageError listing what was tried.
SuiteLocation find_shipped_suite();

}  // namespace rockwatch::cli
