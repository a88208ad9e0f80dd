// The options of the study at scale (study_scaled.hpp): --walls FILE.csv, --shard K/N, --mpi.
#pragma once

#include <string>

#include "rockwatch/options/cli11_fwd.hpp"

#include "study/plan/study_request.hpp"

namespace rockwatch::cli {

struct ScaleOptionTexts {
  std::string walls, shard;
  bool mpi = false;
};

// Registers the options and appends their part of the help's footer.
void add_scale_options(CLI::App& app, ScaleOptionTexts& texts);

// Into the request; throws UsageError naming the option (a K/N that is not 1 <= K <= N, --walls with the wall
// options it replaces, any of them with --observer).
void parse_scale_options(const CLI::App& app, const ScaleOptionTexts& texts, StudyRequest& request);

}  // namespace rockwatch::cli
