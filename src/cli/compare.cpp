// `bagdem compare`: a coupled sweep against the continuum model (command.hpp).
#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/output_lock.hpp"
#include "bagdem/reduce/compare.hpp"
#include "bagdem/reduce/reduce.hpp"
#include "command.hpp"

namespace bagdem::cli {

CLI::App* add_compare(CLI::App& app, Args& a) {
  CLI::App* compare = add_run_reader(app, a, "compare", "For each frequency of a coupled sweep: the response amplitude the DEM produced against the "
                                                        "continuum model's prediction from the DEM-derived C_b, M_b and e (the modal model with the bag's "
                                                        "impedance, the study's SDOF Eq. 7 and Eq. 20), with the errors. Writes OUT/compare.csv (also done at "
                                                        "the end of a sweep).",
                                     "sweep");
  compare->add_option("--form", a.form, "Eq. (7)/(20) form: consistent (default) or printed (the study's as-printed equations)")
      ->check(CLI::IsMember({"consistent", "printed"}));
  return compare;
}

int run_compare(Args& a) {
  apply_fidelity(a);
  const Scene s = load_case(a.case_dir, a.sets);
  refuse_several_dampers(s, "bagdem compare", "compares with the continuum model of one damper");
  if (!s.primary || !s.primary->stepped_sine)
    throw InputError(s.case_file, "excitation.kind", "", "compare needs a coupled stepped-sine sweep (a primary structure with excitation.kind = \"stepped-sine\")");
  const std::optional<OutputLock> lock = lock_existing(a.out());  // not while a run writes there
  const continuum::Form f = a.form == "printed" ? continuum::Form::printed : continuum::Form::consistent;
  const std::vector<CompareRow> rows = compare_with_continuum(*s.primary, s.primary->amplitude, reduce_run(s, a.out()), f);
  write_compare_csv(std::filesystem::path(a.out()) / "compare.csv", rows);
  std::printf("%s", describe_compare(rows, f).c_str());
  return 0;
}

}  // namespace bagdem::cli
