#include "study/study_scaled.hpp"

#include "rockwatch/options/usage_error.hpp"

namespace rockwatch::cli {

int study_merge_main(int, const char* const*) { return 2; }

}  // namespace rockwatch::cli
