// What `rockwatch identify --json` prints (also the Python module's identify(): the same keys).
#pragma once

#include <nlohmann/json.hpp>

#include "identify/identify_request.hpp"
#include "rockwatch/options/wall_file.hpp"
#include "rockwatch/sim/identification.hpp"

namespace rockwatch::cli {

// Exactly the documented keys, in a fixed order; start_r is the energy ratio the fit started from.
nlohmann::ordered_json identify_json(const IdentifyRequest& request, const sim::IdentificationResult& result,
                                     double start_r);

// The wall file --wall-out writes: the identified (equivalent) wall, r, and how they were obtained.
options::WallFile identified_wall_file(const IdentifyRequest& request, const sim::IdentificationResult& result);

}  // namespace rockwatch::cli
