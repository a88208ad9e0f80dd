// The records of a `rockwatch study`, read into the batch engine's form (sim::study::StudyRecord): X and Y of every
// set of a suite with the set's Z as vertical partner, or the lines of a --records list (PATH [VERTICAL_PATH]) read
// as rockwatch simulate reads --record and --vertical.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "rockwatch/sim/study/batch_study.hpp"
#include "study/plan/study_request.hpp"

namespace rockwatch::cli {

// Where one record came from, for the reports and messages.
struct StudyRecordSource {
  std::string path;                          // the file of the horizontal record
  std::optional<std::string> vertical_path;  // the partner's file (for a suite, the same set file); none without
  std::string where;                         // "set 3 X" or "LIST:4": what messages about it name
};

struct StudyRecords {
  std::vector<sim::study::StudyRecord> records;  // a partner only when a case uses it (--vertical with)
  std::vector<StudyRecordSource> sources;        // one per record
  bool from_suite = true;
  std::string suite_dir;                         // with a suite
  std::string suite_name;                        // the set files' suite name, e.g. "npr9998-2015"
  std::string suite_found_by;                    // for the default suite: how it was found; empty for --suite
  std::vector<int> sets;                         // with a suite: the sets studied
  std::string list_path;                         // with --records
  std::vector<std::string> notes;                // the readers' notes and the alignment of partners, for stderr
};

// Reads every record the request names. Throws UsageError naming the option, the list line (LIST:N) or the set at
// fault: a set the suite does not have, a line that is not PATH [VERTICAL_PATH], a record that cannot be read (the
// reader's message after LIST:N), a record with zero peak, a record without partner when --vertical includes with.
StudyRecords load_study_records(const StudyRequest& request);

// "suite npr9998-2015, sets 1-11, components X and Y (22 records), vertical partner Z of the same set" or
// "3 records of LIST (2 with a vertical partner)".
std::string records_text(const StudyRecords& records);

// "1-3,5": a set list as --sets reads it back.
std::string set_list_text(const std::vector<int>& sets);

}  // namespace rockwatch::cli
