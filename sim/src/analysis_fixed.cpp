#include "analysis_fixed.hpp"

namespace rockwatch::sim::detail {

// Placeholder while the fixed-point engine is written (issue 6, same session); replaced before commit.
AnalysisResult analyse_fixed(const core::WallParameters&, const GroundMotion&, const AnalysisOptions&) {
  throw AnalysisError("fixed-point engine not built yet");
}

}  // namespace rockwatch::sim::detail
