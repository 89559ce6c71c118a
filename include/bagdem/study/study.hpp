// Parameter studies over a case: `bagdem sweep`. A study is a base case and a plan of points, each
// the base case with its own `--set` overrides; every point runs as a child process
// (`bagdem run CASE --set ... --out OUT/point-NNN --quiet --threads T`), up to J at once, the ranks
// of an MPI launch sharing the points. The per-point CSV tables are merged into OUT/<name>.csv and
// OUT/study.h5. docs/studies.md describes study.toml and the outputs.
//
// Conventions:
//  - A value is a TOML value as `--set key=value` takes it (a quantity with a unit is a string,
//    "4 mm"); the tables give it as written and as an SI number (units.hpp, parse_quantity).
//  - Points are numbered from 0 in plan order. A grid varies the last key fastest; a zip takes the
//    i-th value of every key together. With seeds N > 1 each combination of values is run with
//    simulation.seed = 1..N (the seed varies fastest: point = combination x N + seed - 1).
//  - A point is done when OUT/point-NNN/point.done exists; it is written (temporary name + rename)
//    only after the child exited 0. Anything else in OUT/point-NNN is never trusted: a restarted
//    sweep deletes such a directory and runs the point again.
//  - Ensemble statistics over the seeds (<name>_ensemble.csv): mean, sample standard deviation
//    s = sqrt(sum (x - mean)^2 / (n - 1)), standard error s / sqrt(n) and the half-width of the 95%
//    interval t_{0.975, n-1} s / sqrt(n) of the n done seeds (reduce/interval.hpp; NaN where n < 2).
//  - Exit codes: 0 every point done, 2 bad input (nothing run, nothing written), 3 a point failed
//    (the others still ran; the tables list it as "failed"), 1 a system error.
// Errors in the input are InputError naming the file (or option), the key, the value and what is
// allowed; a point that does not load is named with its overrides.
#pragma once
#include <cstddef>
#include <filesystem>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "bagdem/case/overrides.hpp"

namespace bagdem::study {

// ---- plan.cpp: the study and its points ---------------------------------------------------------

// One value of a varied key.
struct Value {
  std::string toml;   // in TOML syntax, as --set takes it: "\"4 mm\"", "0.05", "[0, 0, 1]"
  std::string given;  // as written, for the tables: a string's content ("4 mm"), else the TOML text
};

// A varied key of case.toml (dotted) and its values.
struct Varied {
  std::string key;
  std::vector<Value> values;
};

enum class Combine { grid, zip };

// What the user asked for: study.toml (if any) with the command line applied.
struct StudySpec {
  std::string case_dir;                  // the base case (absolute)
  std::string out_dir;                   // OUT (absolute)
  std::string source;                    // where the study came from, for messages ("STUDY/study.toml" or "the command line")
  std::string command = "sweep";         // the command running it, for the progress lines ("characterize", ...)
  Combine combine = Combine::grid;
  std::vector<Varied> vary;              // in the order of the plan (the file's keys, then --vary)
  std::vector<std::string> sets;         // fixed overrides of every point, "key=value"
  int seeds = 1;                         // ensemble size; 1 = the case's own seed, no override
  int jobs = 0, threads = 0, cores = 0;  // 0 = default (see resolve_budget)
  std::vector<std::string> tables = {"reduced", "peaks", "sweep"};  // point tables to merge (NAME.csv)
  std::string fidelity;                  // a preset of bagdem trade ("" = the case as written); its overrides are in sets
};

// The arguments of `bagdem sweep` (add_sweep_command).
struct SweepArgs {
  std::string dir;                        // CASE_DIR (holds case.toml) or STUDY_DIR (holds study.toml)
  std::vector<std::string> vary;          // "key=v1,v2,..."
  std::vector<std::string> sets;          // "key=value"
  bool zip = false;
  bool check = false;                     // --check: plan and load every point, print the plan, run nothing
  std::string fidelity;                   // --fidelity: fast, balanced or reference (study/trade.hpp)
  int seeds = 0, jobs = 0, threads = 0, cores = 0;  // 0: not given
  std::string out;
  std::string executable = "/proc/self/exe";  // what runs the points (tests may point elsewhere)
  std::string command = "sweep";              // the command as its messages name it ("run --seeds" for an ensemble)
};

// study.toml (when args.dir holds one) merged with the command line: --vary of a key the file
// varies replaces its values, other --vary keys are added, --set is appended to the file's set,
// --seeds/--jobs/--threads/--cores/--out/--zip override. Throws InputError.
StudySpec read_spec(const SweepArgs& args);

// A value typed on the command line: TOML if it parses as a TOML value, else a bare string
// (the rule of --set).
Value parse_value(const std::string& text);
// "v1,v2,..." split at the commas outside brackets, braces and quotes, each parsed by parse_value.
std::vector<Value> parse_value_list(const std::string& list);

struct Point {
  std::size_t index = 0;                 // 0-based, the NNN of point-NNN
  std::size_t combination = 0;           // which combination of the varied values (shared by the seeds)
  std::vector<std::size_t> choice;       // per varied key, the index of its value
  int seed = 0;                          // simulation.seed set by the ensemble (0: none set)
  std::vector<std::string> sets;         // every override: the fixed ones, the varied, the seed
  std::string name;                      // "point-003"
  long long case_seed = 0;               // the seed the loaded case resolves to (validate_plan)
  std::string case_hash;                 // hash of the resolved case text (validate_plan)
  std::vector<std::string> scene;        // scene_record of the loaded case (validate_plan)
};

struct Plan {
  StudySpec spec;
  std::vector<Point> points;
  std::string point_dir(const Point& p) const;  // OUT/point-NNN
};

// "point-NNN": index zero-padded to the digits of count - 1 (at least 3).
std::string point_name(std::size_t index, std::size_t count);

// FNV-1a, 64 bits, as 16 hex digits: a fingerprint of a text (a resolved case; not a security measure).
std::string fingerprint(const std::string& text);

// The points of a spec. Throws InputError: a zip of unequal lengths,
// a key both varied and set, simulation.seed varied with seeds > 1, an empty value list.
Plan make_plan(const StudySpec& spec);

// Loads every point's case in-process (bagdem::load_case); the first that fails throws an
// InputError naming the point and its overrides, then the loader's message (file, key, value).
// Fills case_seed, case_hash and scene. Returns the loader's warnings, each once, with the points they
// concern.
std::vector<std::string> validate_plan(Plan& plan);

// The text of OUT/point-NNN/point.toml: the case, the overrides, the varied values, the seed and
// the scene this bagdem resolves them to (scene_record).
std::string point_toml(const Plan& plan, const Point& p);

// What OUT already holds for each point: done (point.done and a point.toml matching the plan),
// or to run (nothing there, or a directory without point.done, which will be deleted).
// Throws InputError "the study changed: ..." when a done point's point.toml differs from the plan
// or OUT holds point directories beyond the plan, and InputError naming the point when one of the
// tables its point.done records (point_tables_text) was changed or removed since its run finished.
std::vector<bool> done_points(const Plan& plan);

// point.done's record of a finished point's tables (its *.csv and *.json, each file's fingerprint,
// as a [tables] TOML table), which done_points checks.
std::string point_tables_text(const std::filesystem::path& dir);

// ---- budget (sweep.cpp): how many children, how many threads each -------------------------------

struct Budget {
  int jobs = 1;          // children at once on this rank
  int threads = 1;       // OpenMP threads per child
  int cores = 1;         // cores this rank may use
  std::string cores_from;  // how `cores` was chosen, for messages
};

// The cores of this process's CPU affinity mask (what nproc prints).
int machine_cores();
// Defaults: T = 1, C = `available` (Ranks::cores(), `available_from` says where it came from),
// J = C / T. Throws InputError (from `command`, e.g. "bagdem sweep") when J x T > C, saying what to
// change.
Budget resolve_budget(const StudySpec& spec, int available, const std::string& available_from, const std::string& command);

// ---- pool.cpp: the points as child processes ----------------------------------------------------

struct PoolOptions {
  std::string executable = "/proc/self/exe";
  int jobs = 1, threads = 1;
  int rank = 0, ranks = 1;               // for point.done, the logs and the progress prefix
  std::size_t total = 0;                 // this rank's share of the plan (done before + to run)
  std::size_t done_before = 0;           // of that share, done by an earlier sweep
};

struct PointOutcome {
  std::size_t index = 0;
  bool done = false;
  int exit_code = 0;                     // the child's exit status; 128 + signal if killed
  double wall_seconds = 0;
};

// Runs the given points (indices into plan.points), at most opt.jobs at once: each in a fresh
// OUT/point-NNN (any previous one deleted) holding point.toml and log.txt (the child's stdout and
// stderr); point.done after exit 0. A line on stderr at each change (done / running / failed /
// left, elapsed, ETA); a failed point is reported with the end of its log. Children get
// PR_SET_PDEATHSIG: they die with the sweep.
std::vector<PointOutcome> run_points(const Plan& plan, const std::vector<std::size_t>& todo, const PoolOptions& opt);

// A study command's body with SIGINT and SIGTERM held (bagdem/interrupt.hpp): its points stop at
// once (run_points throws Interrupted, which the body turns into 130 or 143), while a signal during
// its planning or its merged tables waits until they are written whole; then it says so and
// returns 128 + the signal. Otherwise the body's code.
int holding_interrupts(const std::string& command, const std::function<int()>& body);

// This rank's share of the plan (the points whose index mod `ranks` is `rank`): the points of it
// not `done` run through run_points, budget.jobs at once with budget.threads threads each; a
// resumed share says so on stderr (`prefix` first).
void run_share(const Plan& plan, const std::vector<bool>& done, const Budget& budget, const std::string& executable,
               int rank = 0, int ranks = 1, const std::string& prefix = "");
// Which points of the plan have finished: their point.done exists.
std::vector<bool> finished_points(const Plan& plan);

// ---- tables.cpp: merging the points' tables -----------------------------------------------------

// A CSV table as text cells (the points' own cells are copied, never re-printed).
struct Table {
  std::vector<std::string> columns;      // "name [unit]" or a plain name
  std::vector<std::vector<std::string>> rows;
};

// RFC 4180 CSV (quoted cells may hold commas, quotes, newlines). read_csv throws std::runtime_error
// when the file cannot be read.
Table read_csv(const std::string& path);
std::string csv_text(const Table& t);
// One cell as csv_text writes it: as it is, or quoted with its quotes doubled when it holds a
// comma, a quote or a line break.
std::string csv_cell(const std::string& cell);
// `s` without the spaces, tabs and line breaks at its ends.
std::string trim(const std::string& s);

// A varied value as an SI number: parse_quantity with the dimension its unit has (NaN if it is not
// a number with an optional unit). `unit` gets the SI unit ("m", "1"), or "" for a plain number.
double si_number(const std::string& given, std::string* unit);

// A number as the study commands write it into --set values and their tables (case/overrides.hpp).
using bagdem::short_text;

// OUT/<name>.csv's content: point, status, seed, each varied key as given and as an SI number
// (`<key> [unit]`), then the point's own columns (union over the points, in order of appearance),
// a row per row of the point's NAME.csv; a point without the file gets one row with its own cells
// empty. `done[i]` gives the status. nullopt when no point wrote NAME.csv.
std::optional<Table> merge_table(const Plan& plan, const std::vector<bool>& done, const std::string& name);

// The ensemble over the seeds of a merged table: a row per combination of the varied values and
// row index within the point's table (`row`); `n` the done seeds in it; for each numeric own
// column its mean, sd and se ("<name>_mean [unit]", "_sd", "_se"); a text column is kept when all
// seeds agree.
Table ensemble_table(const Plan& plan, const Table& merged);

// OUT/study.h5: a group per table, a dataset per column named without its unit (numbers float64
// with a "unit" attribute, text as variable-length strings); the columns named by `given_keys`
// (the varied values as written) go to <table>/given/<key>, always as strings. Written to a
// temporary name and renamed.
void write_study_h5(const std::string& path, const std::vector<std::pair<std::string, Table>>& tables,
                    const std::vector<std::string>& given_keys);

// Writes OUT/<name>.csv (and <name>_ensemble.csv with seeds > 1) for every table some point wrote,
// and study.h5; each to a temporary name, then renamed. Returns what was written, e.g.
// {"sweep.csv (6 rows)", "study.h5"}.
std::vector<std::string> merge_tables(const Plan& plan, const std::vector<bool>& done);

// Removes merged tables of an earlier sweep in OUT, so that none outlives the points it summarised,
// and an earlier export of them (reduce/export.hpp, remove_earlier_export).
void remove_merged_tables(const Plan& plan);

// ---- mpi.cpp: the ranks of an MPI launch ---------------------------------------------------------

// The ranks sharing the plan. With MPI in the build (BAGDEM_WITH_MPI) and a launch by mpirun (or
// another PMI launcher), MPI_Init here and MPI_Finalize at destruction; otherwise one rank.
class Ranks {
 public:
  Ranks();
  ~Ranks();
  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  int local_size() const { return local_size_; }  // ranks on this node (they share its cores)
  // This rank's share of the node's cores: its own affinity mask when the launcher bound the
  // node's ranks to disjoint cores, else the cores of all their masks divided among them (at
  // least 1); with one rank, machine_cores(). cores_from() says which, for messages.
  int cores() const { return cores_; }
  const std::string& cores_from() const { return cores_from_; }
  void barrier() const;
  int broadcast(int value) const;  // rank 0's value on every rank
  std::vector<double> broadcast(std::vector<double> values) const;  // rank 0's list on every rank
  int max(int value) const;        // the largest value of all ranks, on every rank
  [[noreturn]] void abort(int code) const;  // ends every rank (a rank failed after the start)

 private:
  int rank_ = 0, size_ = 1, local_size_ = 1;
  int cores_ = 1;
  std::string cores_from_;
  [[maybe_unused]] bool initialised_ = false;  // used only with BAGDEM_MPI (mpi.cpp)
};

// True when this process was started by an MPI launcher (environment of mpirun, srun, hydra).
bool launched_by_mpi();

// ---- sweep.cpp: the command ----------------------------------------------------------------------

// A command that runs a study (sweep, characterize), in the order above: `read` gives the spec
// (an InputError from it is bad input, exit 2, on every rank); with `check` the plan is printed and
// nothing runs; after the merge rank 0 calls `after` (if any) with the points that finished, and
// the command returns the larger of its code and the sweep's (0, or 3 when a point failed).
// `command` names it in messages ("bagdem sweep").
int study_command(const std::function<StudySpec()>& read, bool check, const std::string& executable, const std::string& command,
                  const std::function<int(const Plan&, const std::vector<bool>&)>& after);

// Runs a command's body: its return value, or on an exception "error: <what>" on stderr and its
// exit code (error.hpp, exit_code_of: 2 bad input, 3 a run that went unstable, 1 any other).
int reporting_errors(const std::function<int()>& body);

// ---- The ranks of commands that run several studies in turn (design, calibrate) -----------------

// Starts this process's ranks (MPI's when a launcher started it; else one rank): 0, or the exit code
// after saying why on stderr (an MPI launch of a build without MPI is bad input, 2).
int start_ranks(std::optional<Ranks>& ranks);

// "[rank r/R] " under an MPI launch of several ranks, else "": the prefix of a rank's messages.
std::string rank_prefix(const Ranks& ranks);

// Runs `body` on every rank (reading and validating, the same everywhere) and agrees on the
// outcome before anything is written: the largest exit code of the ranks (an exception's per
// exit_code_of). The lead speaks for all; another rank only when it alone failed.
int agreed(const Ranks& ranks, const std::function<int()>& body);

// A failure of the lead rank's, on the other ranks (run_round).
struct RoundFailed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// One study of a command that runs several in turn (design's maps and its check, calibrate's
// rounds), shared among the ranks as a sweep's points are (index % ranks == rank): the lead makes
// OUT's directory and removes its merged tables, every rank runs its share of the points not done,
// then the lead calls `after` (if any: merging, writing a map) while the others wait. Returns the
// points finished. Whatever it throws, every rank throws: the lead its own exception, the others
// RoundFailed; a rank whose runs cannot start ends every rank (the others would wait for ever).
// `prefix` starts this study's progress lines. The lead alone decides what the next study is and
// sends it (the other ranks never choose from files they may see differently).
std::vector<bool> run_round(const Plan& plan, const std::vector<bool>& done, const Budget& budget, const std::string& executable,
                            const Ranks& ranks, const std::string& prefix, const std::function<void(const std::vector<bool>&)>& after);

// Runs `bagdem sweep`: read, plan, validate (every rank), run this rank's points
// (index % ranks == rank), then rank 0 merges the tables and prints the summary. Returns the exit
// code (the same on every rank).
int sweep_command(const SweepArgs& args);

// ---- ensemble_run.cpp: `bagdem run CASE --seeds N` -------------------------------------------------

// The case as an ensemble of N perturbed starts: a study with no varied key and seeds 1..N (each
// start in OUT/point-NNN, resumable, the cores shared as by `bagdem sweep`), then each mode's peak
// reduction over the starts with its 95% interval, and a warning when the starts gave the same
// results (simulation.seed changed nothing). OUT defaults to CASE_DIR/out. Returns the exit code.
int run_ensemble(const std::string& case_dir, const std::vector<std::string>& sets, int seeds, const std::string& out,
                 int threads);

}  // namespace bagdem::study
