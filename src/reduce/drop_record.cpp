// The drop test's record (reduce/drop_record.hpp).
#include "bagdem/reduce/drop_record.hpp"

#include <toml++/toml.h>

#include <sstream>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "bagdem/fingerprint.hpp"
#include "bagdem/io/atomic_file.hpp"
#include "bagdem/reduce/reduce.hpp"

namespace bagdem {

namespace fs = std::filesystem;

namespace {
fs::path record_of(const fs::path& csv) { return fs::path(csv).replace_extension(".toml"); }
}  // namespace

void write_drop_record(const fs::path& table, const fs::path& csv, const Scene& scene) {
  const auto print = file_fingerprint(table);
  if (!print) throw InputError(table.string(), "", "", "cannot be read back");
  std::ostringstream s;
  s << "# The drop test of drop_result.csv (bagdem drop): the fingerprint of that table as written, and the case it\n"
       "# was run with, as resolved. bagdem reduce attaches its e only to a run of this case (docs/outputs.md).\n"
    << toml::table{{"csv", *print}, {"case", scene.resolved}} << "\n";
  write_atomically(record_of(csv), s.str());
}

bool check_drop_record(const fs::path& csv, const Scene& scene) {
  const fs::path record = record_of(csv);
  if (!fs::exists(record)) return false;
  toml::table t;
  try {
    t = toml::parse_file(record.string());
  } catch (const toml::parse_error& e) {
    throw InputError(record.string(), "", "", std::string("is not a drop test's record: ") + std::string(e.description()));
  }
  const auto print = t["csv"].value<std::string>();
  const auto resolved = t["case"].value<std::string>();
  if (!print || !resolved) throw InputError(record.string(), "", "", "is not as bagdem drop writes it (csv, case): run bagdem drop again");
  if (*print != file_fingerprint(csv).value_or("(unreadable)"))
    throw InputError(csv.string(), "", "", "is not the table bagdem drop wrote (" + record.string() + " records " + *print +
                                               "): it was edited or damaged since. Run bagdem drop again");
  const std::string diff = case_differences(*resolved, scene.resolved, kReducedAtAnyCycles);
  if (!diff.empty())
    throw InputError(csv.string(), "", "", "is the drop test of another case than this run's (" + diff +
                                               "): run bagdem drop with the run's case and --set options, or remove it and its " +
                                               record.filename().string());
  return true;
}

}  // namespace bagdem
