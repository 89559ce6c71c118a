// `bagdem sweep` (study/study.hpp): the command line, the core budget, and the order of the work:
//  1. every rank reads the study, plans it, checks the budget, loads every point's case and
//     compares OUT with the plan, and rank 0 locks OUT (io/output_lock.hpp: a second study into it,
//     or into a directory inside it, is refused meanwhile; the ranks' own runs may write inside
//     it); an error here is the same on every rank: rank 0 prints it, all return 2, nothing is
//     written;
//  2. rank 0 removes merged tables of an earlier sweep; each rank runs its points
//     (index % ranks == rank) that are not done, in its own pool of J children of T threads;
//  3. after a barrier rank 0 merges the tables and prints the summary; every rank returns its code.
// A failure after step 1 on one rank (a full disk, say) aborts every rank, since the others would
// wait at the barrier for ever.
#include <sched.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <functional>
#include <thread>

#include "bagdem/error.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/study/study.hpp"

namespace bagdem::study {
namespace fs = std::filesystem;

int machine_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return std::max(1u, std::thread::hardware_concurrency());
}

Budget resolve_budget(const StudySpec& spec, int available, const std::string& available_from, const std::string& command) {
  Budget b;
  b.threads = spec.threads > 0 ? spec.threads : 1;
  b.cores = spec.cores > 0 ? spec.cores : std::max(1, available);
  b.cores_from = spec.cores > 0 ? "--cores " + std::to_string(spec.cores) : available_from;
  b.jobs = spec.jobs > 0 ? spec.jobs : b.cores / b.threads;
  if (b.jobs < 1 || b.jobs * b.threads > b.cores) {
    const int fit = std::max(1, b.cores / b.threads);
    const int jobs = std::max(1, b.jobs);
    throw InputError(command, "", "",
                     "--jobs " + std::to_string(jobs) + " x --threads " + std::to_string(b.threads) + " = " + std::to_string(jobs * b.threads) +
                         " threads exceed the " + std::to_string(b.cores) + " cores available (" + b.cores_from +
                         "): the runs would compete for cores and each be slower. " +
                         (b.threads > b.cores ? "Lower --threads to at most " + std::to_string(b.cores)
                                              : "Lower --jobs to " + std::to_string(fit) + " (or --threads)") +
                         ", or give --cores if more cores are really free");
  }
  return b;
}

int reporting_errors(const std::function<int()>& body) {
  try {
    return body();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", error_label(e), e.what());
    return exit_code_of(e);
  }
}

int start_ranks(std::optional<Ranks>& ranks) {
  try {
    ranks.emplace();
    return 0;
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kExitInputError;
  }
}

std::string rank_prefix(const Ranks& ranks) {
  return ranks.size() > 1 ? "[rank " + std::to_string(ranks.rank()) + "/" + std::to_string(ranks.size()) + "] " : "";
}

int agreed(const Ranks& ranks, const std::function<int()>& body) {
  int failure = 0;
  std::string message, label = "error";
  try {
    failure = body();
  } catch (const std::exception& e) {
    failure = exit_code_of(e), message = e.what(), label = error_label(e);
  }
  const bool lead = ranks.rank() == 0;
  const int lead_failure = ranks.broadcast(failure);
  if (!message.empty() && (lead || lead_failure == 0))
    std::fprintf(stderr, "%s%s: %s\n", lead ? "" : rank_prefix(ranks).c_str(), label.c_str(), message.c_str());
  return ranks.max(failure);
}

int sweep_command(const SweepArgs& args) {
  return study_command([&] { return read_spec(args); }, args.check, args.executable, "bagdem " + args.command, nullptr);
}

namespace {

// The lead's line of the plan: what is run, where, and on what.
void print_plan(const std::string& command, const Plan& plan, const Budget& budget, const Ranks& ranks) {
  std::string shape;
  if (plan.spec.vary.empty()) shape = "the case as it is";
  else if (plan.spec.combine == Combine::zip)
    shape = "zip of " + std::to_string(plan.spec.vary.size()) + " lists of " + std::to_string(plan.spec.vary[0].values.size()) + " values";
  else
    for (const Varied& v : plan.spec.vary) shape += (shape.empty() ? "grid " : " x ") + std::to_string(v.values.size());
  if (plan.spec.seeds > 1) shape += ", " + std::to_string(plan.spec.seeds) + " seeds each";
  std::fprintf(stderr, "%s %s: %zu points (%s) -> %s; %d rank%s, each running %d at once with %d thread%s on %d cores (%s)\n",
               command.c_str(), plan.spec.case_dir.c_str(), plan.points.size(), shape.c_str(), plan.spec.out_dir.c_str(), ranks.size(),
               ranks.size() > 1 ? "s" : "", budget.jobs, budget.threads, budget.threads > 1 ? "s" : "", budget.cores,
               budget.cores_from.c_str());
}

// --check: each point, whether it is done, and its values.
void print_points(const Plan& plan, const std::vector<bool>& done) {
  for (const Point& p : plan.points) {
    std::string values;
    for (std::size_t k = 0; k < plan.spec.vary.size(); ++k)
      values += (k ? ", " : "") + plan.spec.vary[k].key + " = " + plan.spec.vary[k].values[p.choice[k]].given;
    if (p.seed > 0) values += (values.empty() ? "" : ", ") + std::string("seed ") + std::to_string(p.seed);
    std::printf("%s  %-5s %s\n", p.name.c_str(), done[p.index] ? "done" : "to do", values.c_str());
  }
}

// The merged tables of the points that finished, and the summary; 3 when a point failed.
int merge_points(const Plan& plan, const std::vector<bool>& finished, std::chrono::steady_clock::time_point t0) {
  int code = 0;
  std::vector<std::string> failed;
  for (const Point& p : plan.points)
    if (!finished[p.index]) failed.push_back(p.name);
  const std::vector<std::string> written = merge_tables(plan, finished);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (failed.empty()) {
    std::printf("%s complete: %zu points done, %.1f s wall -> %s\n", plan.spec.command.c_str(), plan.points.size(), wall,
                plan.spec.out_dir.c_str());
  } else {
    std::string list;
    for (std::size_t k = 0; k < failed.size() && k < 10; ++k) list += (k ? ", " : "") + failed[k];
    if (failed.size() > 10) list += ", ...";
    std::printf("%s finished with %zu failed point%s of %zu (%s: see %s log.txt), %.1f s wall -> %s\n", plan.spec.command.c_str(), failed.size(),
                failed.size() > 1 ? "s" : "", plan.points.size(), list.c_str(), failed.size() > 1 ? "their" : "its", wall,
                plan.spec.out_dir.c_str());
    code = kExitRunError;
  }
  if (written.empty()) {
    std::string names;
    for (const std::string& t : plan.spec.tables) names += (names.empty() ? "" : ", ") + t + ".csv";
    std::printf("no point wrote any of %s: no merged tables\n", names.c_str());
  } else {
    std::string list;
    for (const std::string& w : written) list += (list.empty() ? "" : ", ") + w;
    std::printf("tables: %s\n", list.c_str());
  }
  return code;
}

}  // namespace

int study_command(const std::function<StudySpec()>& read, bool check, const std::string& executable, const std::string& command,
                  const std::function<int(const Plan&, const std::vector<bool>&)>& after) {
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<Ranks> ranks;
  if (const int code = start_ranks(ranks)) return code;
  const bool lead = ranks->rank() == 0;
  const std::string prefix = rank_prefix(*ranks);

  // 1. Read, plan, validate: the same on every rank. The ranks agree on the outcome before any
  // writes, so that none runs points while another has stopped.
  Plan plan;
  Budget budget;
  std::vector<bool> done;
  std::vector<std::string> warnings;
  std::optional<OutputLock> lock;  // the lead's, on OUT: one study writes a directory at a time
  if (const int any = agreed(*ranks, [&] {
        plan = make_plan(read());
        budget = resolve_budget(plan.spec, ranks->cores(), ranks->cores_from(), command);
        warnings = validate_plan(plan);
        if (lead && !check) refuse_other_outputs(plan.spec.out_dir, OutputOwner::study), lock.emplace(plan.spec.out_dir);
        if (!check) share_output_with_children(plan.spec.out_dir);  // every rank's runs write inside OUT
        done = done_points(plan);
        return 0;
      }))
    return any;

  try {
    // 2. This rank's points.
    if (lead) {
      for (const std::string& w : warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
      print_plan(command, plan, budget, *ranks);
      if (check) {
        print_points(plan, done);
      } else {
        fs::create_directories(plan.spec.out_dir);
        remove_merged_tables(plan);
      }
    }
    if (check) return 0;
    run_share(plan, done, budget, executable, ranks->rank(), ranks->size(), prefix);

    // 3. Merge.
    ranks->barrier();
    int code = 0;
    if (lead) {
      const std::vector<bool> finished = finished_points(plan);
      code = merge_points(plan, finished, t0);
      if (after) code = std::max(code, after(plan, finished));
      std::fflush(stdout);
    }
    return ranks->broadcast(code);
  } catch (const InputError& e) {  // bad input found as the points run (a point's directory another process holds)
    std::fprintf(stderr, "%serror: %s\n", prefix.c_str(), e.what());
    if (ranks->size() > 1) ranks->abort(2);
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s%s: %s\n", prefix.c_str(), error_label(e), e.what());
    if (ranks->size() > 1) ranks->abort(exit_code_after_runs(e));
    return exit_code_after_runs(e);
  }
}

}  // namespace bagdem::study
