// runs.csv of a `rockwatch study`: one row per finished analysis, in run-index order, written so that it reads back
// into exactly the results it came from (numbers in shortest round-trip form, absent times as empty fields). That
// makes the file the study's checkpoint: --resume reads it and runs only what it lacks, and the final file does not
// depend on how often the study was interrupted or on --jobs.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include "rockwatch/sim/study/batch_study.hpp"

namespace rockwatch::cli {

inline constexpr const char* kRunsCsvName = "runs.csv";

// record,component,vertical,r,pga_g,collapsed,t_collapse_s,t_exceed_s,max_abs_x_m,n_impacts,run
// [,t_first_imminent_s]                                                     with alarms
// [,saturated,collapsed_double,t_collapse_double_s,max_abs_x_double_m
//  [,t_first_imminent_double_s],verdict_differs]                            with fixed-point arithmetic
// [,collapsed_reference,max_abs_x_reference_m],error                                              with the dt check
// In a fixed-point study the first columns are the fixed engine's, the _double ones the double engine's on the same
// input (its verdict is the verdict of record), verdict_differs = collapsed != collapsed_double.
std::string runs_csv_header(const sim::study::StudyPlan& plan);

// The header and one row per done run. A run the engine refused (error) has empty verdict fields. Text fields
// (record names, errors) are quoted as RFC 4180 says when they hold a comma, quote or line break.
void write_runs_csv(std::ostream& out, const sim::study::StudyPlan& plan,
                    const std::vector<sim::study::RunResult>& results);

// Reads a runs.csv written for `plan` into `results` (resized to the plan's run count when empty), marking its rows
// done; returns how many. Throws UsageError naming PATH:LINE when the header is not the plan's, a field is
// malformed, or a row does not belong to the plan (its record, component, vertical, r or PGA differ from those of
// its run index).
std::size_t read_runs_csv(const std::string& path, const sim::study::StudyPlan& plan,
                          std::vector<sim::study::RunResult>& results);

// The pieces of read_runs_csv, for readers of files with more columns in front (a portfolio's wall, study_portfolio):
// one line into its fields (false: an unclosed quote), and one row's fields (the plan's columns) into `results` at
// its run index, returned. Throws UsageError naming `where` ("PATH:LINE") as read_runs_csv does.
bool split_runs_csv_line(const std::string& line, std::vector<std::string>& fields);
std::size_t read_runs_csv_row(const std::string& where, const std::vector<std::string>& fields,
                              const sim::study::StudyPlan& plan, std::vector<sim::study::RunResult>& results);

}  // namespace rockwatch::cli
