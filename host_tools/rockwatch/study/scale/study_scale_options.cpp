#include "study/scale/study_scale_options.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "rockwatch/options/command_line.hpp"
#include "rockwatch/options/option_values.hpp"
#include "rockwatch/options/usage_error.hpp"
#include "common/process/options_namespace.hpp"

namespace rockwatch::cli {

// The helpers in a namespace of their own: the files that include CLI11 are compiled as one unit (CMakeLists.txt),
// and theirs have the same names.
namespace {
namespace study_scale_options {

// At most this many shards: a batch array of a hundred thousand tasks is already beyond what schedulers accept.
constexpr std::uint64_t kMaxShards = 100000;

const char* const kScaleFooter =
    "\n"
    "At scale (a building stock, a cluster):\n"
    "  --walls FILE.csv runs the plan for every wall of a portfolio, one per row under the header\n"
    "                id,b,h1,h2,rho,fp,a,a_prime (m, m, m, kg/m3, N/m, fractions of b; an empty field is the paper's\n"
    "                value; id: letters, digits, _ - .). runs.csv gains a first column wall (the id; run is then the\n"
    "                index within the wall's plan); summary.json holds per wall (\"walls\") its capacities and cases;\n"
    "                walls_summary.csv one row per wall and case: id, r, vertical, fit_mean_g, fit_std_g,\n"
    "                lognormal_median_g, lognormal_beta, p_collapse_ntc2008, p_collapse_nzsee2016,\n"
    "                allowable_pga_ntc2008_g, allowable_pga_nzsee2016_g; with --plots walls_fragility.png (the\n"
    "                lognormal median per case against h/b). No table3.md. The example portfolio of the design\n"
    "                paper's parametric range: sim/portfolios/example_walls.csv.\n"
    "  --shard K/N    runs the K-th of N slices of the plan (runs whose index mod N is K-1) into --out: runs.csv,\n"
    "                study.json and shard.json; `rockwatch study merge --out DIR SHARD_DIR...` checks that the shards\n"
    "                are one plan's, complete, none missing or twice, and writes the study's files, byte for byte\n"
    "                those of the study run in one piece. A killed shard continues with --resume. docs/ has an\n"
    "                sbatch array script (docs/study-array.sbatch).\n"
    "  --mpi          under mpirun: the ranks share the plan (dynamic: a rank asks for the next runs when done);\n"
    "                rank 0 writes the files of the single-process study and the progress; --jobs is per rank\n"
    "                (default 1). SIGINT/SIGTERM saves what is done for --resume.\n"
    "  Examples:\n"
    "    rockwatch study --walls sim/portfolios/example_walls.csv --out stock --plots\n"
    "    rockwatch study --shard 3/8 --out shard3 ...; rockwatch study merge --out study shard1 ... shard8\n"
    "    mpirun -np 64 rockwatch study --mpi --walls stock.csv --out stock\n";

}  // namespace study_scale_options
}  // namespace

void add_scale_options(CLI::App& app, ScaleOptionTexts& texts) {
  using namespace study_scale_options;
  app.add_option("--walls", texts.walls, "Portfolio of walls, a CSV file (id,b,h1,h2,rho,fp,a,a_prime): the study "
                                         "for each")
      ->type_name("FILE.csv");
  app.add_option("--shard", texts.shard, "Run only the K-th of N slices of the plan (1 <= K <= N); merge the "
                                         "shards with `rockwatch study merge`")
      ->type_name("K/N");
  app.add_flag("--mpi", texts.mpi, "Share the plan among the ranks of an MPI job (mpirun -np N rockwatch study --mpi)");
  app.footer(app.get_footer() + kScaleFooter);
}

void parse_scale_options(const CLI::App& app, const ScaleOptionTexts& texts, StudyRequest& q) {
  using namespace study_scale_options;
  const bool walls = given(app, "--walls"), shard = given(app, "--shard");
  if ((walls || shard || texts.mpi) && q.forecast) {
    throw UsageError(std::string(walls ? "--walls" : shard ? "--shard" : "--mpi") +
                     " cannot be combined with --forecast: run the forecast evaluation as a study of its own");
  }
  if ((walls || shard || texts.mpi) && q.observer) {
    throw UsageError(std::string(walls ? "--walls" : shard ? "--shard" : "--mpi") +
                     " cannot be combined with --observer: run the observer evaluation as a study of its own");
  }
  if (walls) {
    for (const char* option : {"--wall", "--b", "--h1", "--h2", "--rho", "--fp", "--a", "--a-prime"}) {
      if (given(app, option)) {
        throw UsageError(std::string("--walls gives every wall's parameters (an empty field is the paper's value): it "
                                     "cannot be combined with ") + option);
      }
    }
    if (texts.walls.empty()) throw UsageError("--walls needs a CSV file name");
    check_input_file("--walls", texts.walls, "a CSV file of walls (id,b,h1,h2,rho,fp,a,a_prime)");
    q.walls_file = texts.walls;
  }
  if (shard) {
    const std::string expected = "--shard must be K/N, two whole numbers with 1 <= K <= N <= " +
                                 std::to_string(kMaxShards) + ", e.g. 3/8 (got " + options::quoted(texts.shard) + ")";
    const std::vector<std::string> parts = split_fields(texts.shard, '/');
    if (parts.size() != 2) throw UsageError(expected);
    const std::optional<std::uint64_t> n = whole_number(parts[1], 1, kMaxShards);
    const std::optional<std::uint64_t> k = whole_number(parts[0], 1, kMaxShards);
    if (!n || !k || *k > *n) throw UsageError(expected);
    q.shard_index = static_cast<std::size_t>(*k);
    q.shard_count = static_cast<std::size_t>(*n);
  }
  q.mpi = texts.mpi;
  if (q.mpi && !given(app, "--jobs")) q.jobs = 1;  // a rank per core: threads on top would oversubscribe
}

}  // namespace rockwatch::cli
