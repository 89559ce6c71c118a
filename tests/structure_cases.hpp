// Test support: the structure suites' cases (test_structure.cpp, test_dampers.cpp): soft balls in a
// box on a primary structure, through case files.
#pragma once
#include <sstream>
#include <string>
#include <vector>

#include "bagdem/case/load_case.hpp"
#include "bagdem/error.hpp"
#include "support.hpp"

namespace bagdem::testing::structure_cases {

// A case with soft balls in a box; `sections` adds [primary], [excitation], [particles...].
inline std::string case_text(const std::string& sections, const std::string& simulation = "duration = \"0.1 s\"") {
  std::ostringstream s;
  s << "[simulation]\n" << simulation << "\ngravity = [0, 0, \"-9.81 m/s^2\"]\n\n"
    << "[materials.soft]\ndensity = \"7800 kg/m^3\"\nyoungs_modulus = \"10 MPa\"\npoisson_ratio = 0.3\n\n"
    << "[interactions.default]\nrestitution = 0.5\nfriction = 0.3\n\n"
    << "[cavity]\nkind = \"box\"\nmaterial = \"soft\"\nmin = [\"-20 mm\", \"-20 mm\", \"-20 mm\"]\n"
    << "max = [\"20 mm\", \"20 mm\", \"20 mm\"]\n\n"
    << sections << "\n[output]\nenergy = true\n";
  return s.str();
}

// One ball at the centre, no gravity: it never touches a wall while the box moves less than 15 mm.
inline constexpr const char* kLoneBall = "[particles.ball]\nmaterial = \"soft\"\ndiameter = \"5 mm\"\npositions = [[0, 0, 0]]\n";

inline Scene load(const TempDir& d, const std::string& text, const std::vector<std::string>& sets = {}) {
  d.write("case.toml", text);
  return load_case(d.str(), sets);
}

inline std::string input_error(const TempDir& d, const std::string& text) {
  try {
    load(d, text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(accepted)";
}

// A pinned-pinned beam of 1 m, 1 kg/m, EI = 10.13 N m^2: modes at 5, 20, 45 Hz.
inline std::string beam_keys(double attach, const std::string& more = "") {
  std::ostringstream b;
  b << "[primary]\nkind = \"beam\"\nlength = \"1 m\"\nyoungs_modulus = 10.1321\nsecond_moment = 1\n"
    << "line_density = \"1 kg/m\"\nends = \"pinned-pinned\"\nmodes = 6\nattach = " << attach << "\n"
    << "force_at = 0.13\nresponse_at = 0.13\n" << more;
  return b.str();
}

// 12 soft 8-mm balls lying on the floor of the box (clearance 16 mm across e = y).
inline constexpr const char* kBalls = "[particles.balls]\nmaterial = \"soft\"\ndiameter = \"8 mm\"\ncount = 12\nfill = \"lattice\"\n";

}  // namespace bagdem::testing::structure_cases
