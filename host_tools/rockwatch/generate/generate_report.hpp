// What `rockwatch generate` writes and prints about a suite: the manifest (JSON) and its CSV table, the set files'
// header fields, the summary for engineers and the list of what was not accepted.
#pragma once

#include <array>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "generate/generate_request.hpp"
#include "rockwatch/core/design_spectrum.hpp"
#include "rockwatch/records/suite_format.hpp"
#include "rockwatch/sim/intensity_measures.hpp"
#include "rockwatch/sim/synthesis/ground_motion_generator.hpp"

namespace rockwatch::cli {

// The generated suite with what the reports say about each record.
struct GeneratedSuite {
  std::vector<sim::synthesis::GeneratedSet> sets;
  std::vector<std::array<sim::IntensityMeasures, 3>> measures;  // per set: X, Y, Z (sim::intensity_measures)
  sim::synthesis::SuiteMean mean;
};

inline constexpr const char* kManifestCsvName = "manifest.csv";
inline constexpr const char* kManifestCsvHeader =
    "set,component,seed,pga_mps2,pga_g,pgv_mps,pgd_m,d5_75_s,d5_95_s,arias_mps,spectral_ratio_min,"
    "spectral_ratio_max,spectrum_accepted,durations_accepted,accepted,attempts,final_velocity_mps,"
    "final_displacement_m";

// "set01.txt": two digits keep an 11-set suite sorted by name.
std::string set_file_name(int set);

// "rockwatch 0.4.0 generate --sets 11 --seed 9998 ...": the set files' generator field (no --out, so the same
// settings give the same files wherever they are written).
std::string generator_text(const GenerateRequest& request);

// "rockwatch generate --out DIR --sets 11 ...": the manifest's command, ready to paste into a shell.
std::string regenerating_command(const GenerateRequest& request);

// "npr9998-2015 p=2.5 tb_s=0.15 tc_s=0.4 td_s=0.67": a target as the set files' header names it.
std::string target_header_text(const core::SpectrumShape& shape);

// The set file of one generated set, ready for records::write_suite_record.
records::SuiteRecordFile suite_record_file(const GenerateRequest& request, const sim::synthesis::GeneratedSet& set);

// The manifest: "format", "version", "suite", "sets" (each "set", "file" and per component the measures) as
// records/suite_format.hpp documents, plus "command", "generator", "accepted", "settings" and "suite_mean".
// Durations that do not exist (a silent record) are null.
nlohmann::ordered_json manifest_json(const GenerateRequest& request, const GeneratedSuite& suite);

// Header and one row per record (set, component), numbers in shortest round-trip form, an empty field for an
// undefined duration; the caller checks the stream.
void write_manifest_csv(std::ostream& out, const GeneratedSuite& suite, double g_mps2);

// Multi-line, human-readable summary ending with a newline.
std::string generate_summary_text(const GenerateRequest& request, const GeneratedSuite& suite);

// One line per record or suite mean that failed its acceptance check, e.g.
// "set 2 Y: spectral ratio 0.853 to 1.21, outside [0.9, 1.3] over 0.05-2.5 s (best of 40 draws)"; empty when the
// whole suite is accepted.
std::vector<std::string> not_accepted(const GenerateRequest& request, const GeneratedSuite& suite);

}  // namespace rockwatch::cli
