// [primary] and [excitation]: the structure carrying the cavity and what drives it
// (structure/primary.hpp). The table of kinds below is the only list.
//   prescribed  (default) the cavity follows [cavity.motion]
//   sdof        mass, stiffness, damping | damping_ratio
//   beam        length, youngs_modulus, second_moment | outer_diameter (+ inner_diameter),
//               line_density | mass, ends, modes, damping_ratio (number or list per mode),
//               attach, force_at, response_at, suspension_frequency, suspension_damping_ratio
//   fe-beam     the beam's keys as defaults, plus [[primary.segments]] (from, to, and any of the
//               section keys above) and [[primary.masses]] (at, mass, inertia), elements
//   modal       table (a CSV of modes, structure/modal_table.hpp), damping_ratio (overrides the
//               table's, as for beam), structure_mass, follow_slope
// All kinds: direction (the transverse direction e, default [0, 1, 0]), axis (along the beam,
// default [1, 0, 0]), cavity_mass. The cavity's reference point (cavity.reference) sits at x_b.
// [excitation] kinds: harmonic, stepped-sine, decay, impulse, random, none (docs/case-schema.md).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <sstream>

#include "bagdem/case/load_case.hpp"
#include "bagdem/case/overrides.hpp"
#include "bagdem/structure/excitation.hpp"
#include "bagdem/structure/modal_table.hpp"
#include "bagdem/structure/modes.hpp"

namespace bagdem {
namespace {

constexpr double kPi = std::numbers::pi;

// Half the cavity's extent along the axis, about its reference point.
double half_extent(const Scene& s, const Vec3& axis) {
  double l = 0;
  for (int c = 0; c < 8; ++c) {
    const Vec3 corner((c & 1) ? s.cavity_hi.x() : s.cavity_lo.x(), (c & 2) ? s.cavity_hi.y() : s.cavity_lo.y(),
                      (c & 4) ? s.cavity_hi.z() : s.cavity_lo.z());
    l = std::max(l, std::abs((corner - s.cavity_reference).dot(axis)));
  }
  return l;
}

double positive(const CaseReader& in, const std::string& key, Dimension d, const char* unit) {
  const double v = in.quantity(key, d);
  if (!(v > 0) || !std::isfinite(v)) in.fail(key, std::string("must be > 0 (") + unit + ")");
  return v;
}

Primary sdof(const CaseReader& in, const Scene&) {
  const double M = positive(in, "primary.mass", dim::mass, "kg");
  const double K = positive(in, "primary.stiffness", dim::stiffness, "N/m");
  const bool by_ratio = in.has("primary.damping_ratio");
  if (by_ratio && in.has("primary.damping")) in.fail("primary.damping", "give either damping (N s/m) or damping_ratio, not both");
  double C = 0;
  if (by_ratio) {
    const double z = in.quantity("primary.damping_ratio", dim::none);
    if (!(z >= 0)) in.fail("primary.damping_ratio", "must be >= 0");
    C = 2 * z * std::sqrt(K * M);
  } else {
    C = in.quantity("primary.damping", dim::damping, 0.0);
    if (!(C >= 0)) in.fail("primary.damping", "must be >= 0 (N s/m)");
  }
  const double mc = in.quantity("primary.cavity_mass", dim::mass, 0.0);
  if (!(mc >= 0)) in.fail("primary.cavity_mass", "must be >= 0 (kg)");
  return make_sdof_primary(M, K, C, mc);
}

// A section's E, I and rhoA from the keys under `prefix`; a key not given comes from `base` (the
// beam's own keys, for a segment of a stepped beam) when there is one.
struct Section {
  double E = 0, I = 0, rhoA = 0;
};
Section read_section(const CaseReader& in, const std::string& prefix, double length, const Section* base) {
  Section sec;
  const std::string E_key = prefix + "youngs_modulus", I_key = prefix + "second_moment";
  const std::string D_key = prefix + "outer_diameter", d_key = prefix + "inner_diameter";
  const bool has_I = in.has(I_key), has_D = in.has(D_key);
  sec.E = base && !in.has(E_key) ? base->E : positive(in, E_key, dim::pressure, "Pa");
  if (has_I && has_D) in.fail(I_key, "give either second_moment or outer_diameter (with inner_diameter for a tube), not both");
  if (has_I) {
    sec.I = positive(in, I_key, dim::area_moment, "m^4");
  } else if (has_D) {
    const double D = positive(in, D_key, dim::length, "m");
    const double d = in.quantity(d_key, dim::length, 0.0);
    if (!(d >= 0 && d < D)) in.fail(d_key, "must be in [0, outer_diameter)");
    sec.I = kPi * (std::pow(D, 4) - std::pow(d, 4)) / 64;
  } else if (base) {
    sec.I = base->I;
  } else {
    in.fail(I_key, "is required: give second_moment (m^4) or outer_diameter (with inner_diameter for a tube)");
  }
  const std::string rho_key = prefix + "line_density", m_key = prefix + "mass";
  const bool has_rho = in.has(rho_key), has_m = in.has(m_key);
  if (base && !has_rho && !has_m) {
    sec.rhoA = base->rhoA;
  } else {
    if (has_rho == has_m) in.fail(has_rho ? rho_key : m_key, "give either line_density (kg/m) or mass (kg)");
    sec.rhoA = has_rho ? positive(in, rho_key, dim::line_density, "kg/m") : positive(in, m_key, dim::mass, "kg") / length;
  }
  return sec;
}

BeamEnds read_ends(const CaseReader& in) {
  const std::string e = in.choice("primary.ends", {"free-free", "pinned-pinned", "clamped-free", "clamped-clamped"}, "free-free");
  BeamEnds ends{};
  parse_beam_ends(e, ends);
  return ends;
}

std::vector<double> read_ratios(const CaseReader& in, const std::string& key, double fallback) {
  std::vector<double> z;
  if (in.has(key) && in.root().at_path(key).is_array()) {
    const std::size_t n = in.array_size(key);
    if (n == 0) in.fail(key, "must not be an empty list");
    for (std::size_t k = 0; k < n; ++k) z.push_back(in.quantity(key + "." + std::to_string(k), dim::none));
  } else {
    z.push_back(in.quantity(key, dim::none, fallback));
  }
  for (double v : z)
    if (!(v >= 0 && v < 1)) in.fail(key, "must be in [0, 1) (a number, or a list with one per elastic mode)");
  return z;
}

// What both beam kinds share: the points, damping, suspension; then the primary from the modes.
Primary beam_from_modes(const CaseReader& in, const Scene& s, const std::string& kind, std::shared_ptr<const ModeSet> modes,
                        double structure_mass, const Vec3& axis) {
  BeamPrimarySpec b;
  b.kind = kind;
  const double L = modes->length();
  auto point = [&](const std::string& key, const double* fallback) {
    const double x = fallback ? in.quantity(key, dim::length, *fallback) : in.quantity(key, dim::length);
    if (!(x >= 0 && x <= L)) in.fail(key, "must lie on the beam, in [0, " + std::to_string(L) + "] m");
    return x;
  };
  const double mid = 0.5 * L;
  b.attach = point("primary.attach", &mid);
  b.force_at = point("primary.force_at", nullptr);
  b.response_at = point("primary.response_at", nullptr);
  b.half_extent = half_extent(s, axis);
  if (b.attach - b.half_extent < 0 || b.attach + b.half_extent > L) {
    std::ostringstream m;
    m << "puts the cavity (" << 2 * b.half_extent << " m long along the axis) beyond the beam's ends; move it to ["
      << b.half_extent << ", " << L - b.half_extent << "] m";
    in.fail("primary.attach", m.str());
  }
  b.zeta = read_ratios(in, "primary.damping_ratio", 0.005);
  b.follow_slope = in.boolean("primary.follow_slope", true);
  b.suspension_frequency = in.quantity("primary.suspension_frequency", dim::frequency, 1.0);
  b.suspension_damping = in.quantity("primary.suspension_damping_ratio", dim::none, 0.05);
  if (!(b.suspension_frequency > 0)) in.fail("primary.suspension_frequency", "must be > 0 (Hz)");
  if (!(b.suspension_damping >= 0)) in.fail("primary.suspension_damping_ratio", "must be >= 0");
  b.cavity_mass = in.quantity("primary.cavity_mass", dim::mass, 0.0);
  if (!(b.cavity_mass >= 0)) in.fail("primary.cavity_mass", "must be >= 0 (kg)");
  b.structure_mass = structure_mass;
  b.modes = std::move(modes);
  return make_beam_primary(b);
}

std::size_t mode_count(const CaseReader& in) {
  const long long n = in.integer("primary.modes", 4);
  if (n < 1 || n > 60) in.fail("primary.modes", "must be in [1, 60] (elastic modes kept)");
  return static_cast<std::size_t>(n);
}

Primary beam(const CaseReader& in, const Scene& s, const Vec3& axis) {
  UniformBeam u;
  u.length = positive(in, "primary.length", dim::length, "m");
  const Section sec = read_section(in, "primary.", u.length, nullptr);
  u.EI = sec.E * sec.I, u.rhoA = sec.rhoA;
  u.ends = read_ends(in);
  return beam_from_modes(in, s, "beam", analytic_beam_modes(u, mode_count(in), true), u.rhoA * u.length, axis);
}

Primary fe_beam(const CaseReader& in, const Scene& s, const Vec3& axis) {
  FeBeam fe;
  fe.length = positive(in, "primary.length", dim::length, "m");
  fe.ends = read_ends(in);
  const std::size_t ns = in.array_size("primary.segments");
  std::optional<Section> base;
  if (ns == 0 || in.has("primary.youngs_modulus") || in.has("primary.line_density") || in.has("primary.mass"))
    base = read_section(in, "primary.", fe.length, nullptr);
  double mass = 0;
  if (ns == 0) {
    fe.segments.push_back({0.0, fe.length, base->E * base->I, base->rhoA});
  } else {
    double at = 0;
    for (std::size_t k = 0; k < ns; ++k) {
      const std::string p = "primary.segments." + std::to_string(k) + ".";
      BeamSegment g;
      g.x0 = in.quantity(p + "from", dim::length, at);
      g.x1 = in.quantity(p + "to", dim::length);
      if (std::abs(g.x0 - at) > 1e-9 * fe.length) in.fail(p + "from", "segments must follow each other from 0 without gaps (expected " + std::to_string(at) + " m)");
      if (!(g.x1 > g.x0 && g.x1 <= fe.length * (1 + 1e-12))) in.fail(p + "to", "must be above `from` and at most the length");
      const Section sec = read_section(in, p, g.x1 - g.x0, base ? &*base : nullptr);
      g.EI = sec.E * sec.I, g.rhoA = sec.rhoA;
      fe.segments.push_back(g);
      at = g.x1;
    }
    if (std::abs(at - fe.length) > 1e-9 * fe.length) in.fail("primary.segments", "must cover the beam up to its length " + std::to_string(fe.length) + " m");
  }
  for (const auto& g : fe.segments) mass += g.rhoA * (g.x1 - g.x0);
  for (std::size_t k = 0; k < in.array_size("primary.masses"); ++k) {
    const std::string p = "primary.masses." + std::to_string(k) + ".";
    LumpedMass m;
    m.x = in.quantity(p + "at", dim::length);
    m.mass = in.quantity(p + "mass", dim::mass);
    m.inertia = in.quantity(p + "inertia", dim::inertia, 0.0);
    if (!(m.x >= 0 && m.x <= fe.length)) in.fail(p + "at", "must lie on the beam");
    if (!(m.mass >= 0) || !(m.inertia >= 0)) in.fail(p + "mass", "mass and inertia must be >= 0");
    fe.masses.push_back(m);
    mass += m.mass;
  }
  const long long ne = in.integer("primary.elements", 200);
  if (ne < 4 || ne > 5000) in.fail("primary.elements", "must be in [4, 5000]");
  fe.elements = static_cast<std::size_t>(ne);
  const std::size_t rigid = fe.ends == BeamEnds::free_free ? 2 : 0;
  return beam_from_modes(in, s, "fe-beam", fe_beam_modes(fe, mode_count(in) + rigid), mass, axis);
}

Primary modal(const CaseReader& in, const Scene& s, const Vec3& axis) {
  ModalPrimarySpec m;
  m.source = in.string("primary.table");
  const std::filesystem::path path = in.file_path("primary.table", s.case_dir);
  if (!std::filesystem::is_regular_file(path)) in.fail("primary.table", "names no file (" + path.string() + "): give the CSV of the modes, relative to the case directory");
  m.table = read_modal_table(path);
  if (in.has("primary.damping_ratio")) {  // one for every elastic mode, or a list in their order
    const std::vector<double> z = read_ratios(in, "primary.damping_ratio", 0.0);
    std::size_t elastic = 0;
    for (ModalRow& r : m.table.rows)
      if (!r.rigid_body) r.damping_ratio = z[std::min(elastic++, z.size() - 1)];
  }
  m.follow_slope = in.boolean("primary.follow_slope", m.table.has_slope);
  if (m.follow_slope && !m.table.has_slope) in.fail("primary.follow_slope", "needs the table's column slope_attach [1/m]");
  m.half_extent = half_extent(s, axis);
  m.cavity_mass = in.quantity("primary.cavity_mass", dim::mass, 0.0);
  if (!(m.cavity_mass >= 0)) in.fail("primary.cavity_mass", "must be >= 0 (kg)");
  m.structure_mass = in.quantity("primary.structure_mass", dim::mass, 0.0);
  if (!(m.structure_mass >= 0)) in.fail("primary.structure_mass", "must be >= 0 (kg; the structure's mass, for bag.balls.mass_ratio)");
  return make_modal_primary(m);
}

struct PrimaryKind {
  const char* name;
  Primary (*make)(const CaseReader&, const Scene&, const Vec3& axis);
};
Primary sdof_kind(const CaseReader& in, const Scene& s, const Vec3&) { return sdof(in, s); }
const PrimaryKind kPrimaryKinds[] = {{"sdof", sdof_kind}, {"beam", beam}, {"fe-beam", fe_beam}, {"modal", modal}};

// ---- [excitation] --------------------------------------------------------------------------------

std::vector<double> number_list(const CaseReader& in, const std::string& key, Dimension d) {
  std::vector<double> v;
  for (std::size_t k = 0; k < in.array_size(key); ++k) v.push_back(in.quantity(key + "." + std::to_string(k), d));
  return v;
}

// Speed amplitude of the cavity in the bare structure's steady state at w under force amplitude F.
double cavity_speed(const Primary& p, double F, double w) { return w * p.bare_cavity_amplitude(F, w); }

// excitation.kind = "stepped-sine": its frequencies (into f) and how a point is judged steady.
std::shared_ptr<Primary::SteppedSine> stepped_sine(const CaseReader& in, const Primary& p, std::vector<double>& f) {
  auto sw = std::make_shared<Primary::SteppedSine>();
  const bool has_list = in.has("excitation.frequencies"), has_band = in.has("excitation.band"),
             has_modes = in.has("excitation.around_modes");
  if (has_list + has_band + has_modes != 1)
    in.fail("excitation", "a stepped-sine sweep needs exactly one of frequencies = [...], band = [lo, hi] (with points), or around_modes = [...] (with span and points)");
  const long long pts = in.integer("excitation.points", has_band ? 41 : 9);
  if (pts < 1 || pts > 100000) in.fail("excitation.points", "must be in [1, 100000]");
  if (has_list) {
    f = number_list(in, "excitation.frequencies", dim::frequency);
  } else if (has_band) {
    const std::vector<double> band = number_list(in, "excitation.band", dim::frequency);
    if (band.size() != 2 || !(band[0] > 0 && band[1] >= band[0])) in.fail("excitation.band", "must be [lo, hi] with 0 < lo <= hi (Hz)");
    for (long long k = 0; k < pts; ++k)
      f.push_back(pts == 1 ? band[0] : band[0] + (band[1] - band[0]) * static_cast<double>(k) / static_cast<double>(pts - 1));
  } else {
    const double span = in.quantity("excitation.span", dim::none, 0.1);
    if (!(span > 0 && span < 1)) in.fail("excitation.span", "must be in (0, 1): the band is f_mode (1 -/+ span)");
    const std::vector<double> bare = p.bare_frequencies();
    std::vector<std::size_t> elastic;
    for (std::size_t k = 0; k < p.size(); ++k)
      if (!p.rigid_body[k]) elastic.push_back(k);
    for (std::size_t i = 0; i < in.array_size("excitation.around_modes"); ++i) {
      const std::string key = "excitation.around_modes." + std::to_string(i);
      const long long m = in.integer(key, 0);
      if (m < 1 || static_cast<std::size_t>(m) > elastic.size())
        in.fail(key, "must name an elastic mode of the primary, 1 to " + std::to_string(elastic.size()));
      const std::size_t dof = elastic[static_cast<std::size_t>(m - 1)];
      sw->modes.push_back(dof);
      // Around the bare mode's frequency with the cavity mass (the DOFs are in frequency order,
      // and a cavity mass keeps that order).
      const double fm = bare[dof];
      for (long long k = 0; k < pts; ++k)
        f.push_back(fm * (1 - span + 2 * span * (pts == 1 ? 0.5 : static_cast<double>(k) / static_cast<double>(pts - 1))));
    }
  }
  if (f.empty()) in.fail("excitation", "the sweep has no frequencies");
  for (double x : f)
    if (!(x > 0)) in.fail("excitation.frequencies", "must all be > 0 (Hz)");
  // One response per frequency: the peak search would take either of two at one frequency.
  std::vector<double> sorted = f;
  std::sort(sorted.begin(), sorted.end());
  if (const auto twice = std::adjacent_find(sorted.begin(), sorted.end()); twice != sorted.end()) {
    const char* key = has_list ? "excitation.frequencies" : has_band ? "excitation.band" : "excitation.around_modes";
    in.fail(key, "gives " + short_text(*twice) + " Hz twice: a sweep visits each frequency once" +
                     (has_band ? " (a band of lo = hi has one point: points = 1)"
                      : has_modes ? " (a mode named twice, or two modes' bands that share a frequency: name each mode once, or "
                                    "narrow excitation.span so that the bands do not meet)"
                                  : ""));
  }
  sw->frequencies = f;
  sw->tolerance = in.quantity("excitation.steady_tolerance", dim::none, 0.01);
  if (!(sw->tolerance > 0)) in.fail("excitation.steady_tolerance", "must be > 0");
  auto count = [&](const char* key, long long fallback) {
    const long long v = in.integer(key, fallback);
    if (v < 1 || v > 1000000) in.fail(key, "must be a whole number in [1, 1e6]");
    return static_cast<std::size_t>(v);
  };
  sw->cycles = count("excitation.steady_cycles", 3);
  sw->min_cycles = count("excitation.min_cycles", 5);
  sw->max_cycles = count("excitation.max_cycles", 200);
  const long long reduce_cycles = in.integer("excitation.reduce_cycles", 10);
  if (reduce_cycles < 3 || reduce_cycles > 1000000)
    in.fail("excitation.reduce_cycles", "must be a whole number in [3, 1e6] (the steady cycles each point is reduced over; the window is the even number of cycles at or above it, so an interval has at least 4)");
  sw->reduce_cycles = static_cast<std::size_t>(reduce_cycles);
  if (sw->max_cycles < sw->min_cycles) in.fail("excitation.max_cycles", "must be >= min_cycles");
  if (sw->max_cycles < sw->reduce_cycles) in.fail("excitation.max_cycles", "must be >= reduce_cycles");
  const long long refine = in.integer("excitation.refine", 4);
  if (refine < 0 || refine > 50) in.fail("excitation.refine", "must be in [0, 50] (extra points per mode near its peak)");
  sw->refine = static_cast<std::size_t>(refine);
  // The chains: the points' split among simulations run side by side. The case sets it, never
  // the thread count, so the results are the same for any --threads.
  const long long chains = in.integer("excitation.chains", 2);
  if (chains < 1 || chains > 1024)
    in.fail("excitation.chains", "must be a whole number in [1, 1024] (simulations that share the frequencies, run side by side; 1 = one after another from a single start)");
  sw->chains = static_cast<std::size_t>(chains);
  sw->predict = in.boolean("excitation.predict", true);
  return sw;
}

// excitation.kind = "decay": a mode's free decay from a displacement at response_at.
void decay_excitation(const CaseReader& in, Primary& p) {
  const double X = in.quantity("excitation.displacement", dim::length);
  if (!(X != 0) || !std::isfinite(X)) in.fail("excitation.displacement", "must be a non-zero displacement at response_at (m)");
  std::size_t dof = 0;
  if (p.kind != "sdof") {
    std::vector<std::size_t> elastic;
    for (std::size_t k = 0; k < p.size(); ++k)
      if (!p.rigid_body[k]) elastic.push_back(k);
    const long long m = in.integer("excitation.mode", 1);
    if (m < 1 || static_cast<std::size_t>(m) > elastic.size()) in.fail("excitation.mode", "must name an elastic mode, 1 to " + std::to_string(elastic.size()));
    dof = elastic[static_cast<std::size_t>(m - 1)];
  }
  const double phi = p.at_response[static_cast<Eigen::Index>(dof)];
  if (std::abs(phi) < 1e-9 * p.at_response.cwiseAbs().maxCoeff())
    in.fail("excitation.mode", "has a node at primary.response_at: its displacement there cannot be set; move response_at");
  p.q0[static_cast<Eigen::Index>(dof)] = X / phi;
  const double w = std::sqrt(p.stiffness[static_cast<Eigen::Index>(dof)] / p.mass(static_cast<Eigen::Index>(dof), static_cast<Eigen::Index>(dof)));
  p.expected_cavity_speed = w * std::abs(p.at_cavity.dot(p.q0));
  p.response_frequency = w / (2 * kPi);
  p.excitation = make_no_force();
}

// excitation.kind = "impulse": a hammer blow at force_at.
void impulse_excitation(const CaseReader& in, Primary& p) {
  const double J = in.quantity("excitation.impulse", dim::impulse);
  const double tau = in.quantity("excitation.duration", dim::time, 2e-4);
  const double t0 = in.quantity("excitation.start_time", dim::time, 0.0);
  if (!(J != 0) || !std::isfinite(J)) in.fail("excitation.impulse", "must be a non-zero impulse (N s)");
  if (!(tau > 0)) in.fail("excitation.duration", "must be > 0 (s)");
  if (!(t0 >= 0)) in.fail("excitation.start_time", "must be >= 0 (s)");
  p.excitation = make_impulse_force(J, tau, t0);
  p.force_time_scale = tau;
  // The blow's velocity at the cavity: J phi_f phi_b per mode (mass-normalised), summed in magnitude.
  p.expected_cavity_speed = std::abs(J) * (p.mass_inverse * p.at_force).cwiseAbs().dot(p.at_cavity.cwiseAbs());
}

// excitation.kind = "random": a band-limited random force (a multisine) at force_at.
void random_excitation(const CaseReader& in, const Scene& s, Primary& p) {
  const double rms = in.quantity("excitation.rms", dim::force);
  const std::vector<double> band = number_list(in, "excitation.band", dim::frequency);
  if (!(rms > 0)) in.fail("excitation.rms", "must be > 0 (N)");
  if (band.size() != 2 || !(band[0] > 0 && band[1] > band[0])) in.fail("excitation.band", "must be [lo, hi] with 0 < lo < hi (Hz)");
  const auto seed = static_cast<std::uint64_t>(in.integer("excitation.seed", static_cast<long long>(s.seed), 0, kMaxSeed));
  const double period = in.quantity("excitation.period", dim::time, 0.0);
  if (!(period >= 0)) in.fail("excitation.period", "must be >= 0 (s; 0 = automatic)");
  if ((band[1] - band[0]) * period > 20000) in.fail("excitation.period", "gives more than 20000 lines in the band (lines = band width x period); shorten it");
  p.excitation = make_random_force(rms, band[0], band[1], seed, period);
  p.random_lo = band[0], p.random_hi = band[1], p.random_rms = rms;
  const double T = period > 0 ? period : 200.0 / (band[1] - band[0]);  // as make_random_force's
  p.random_lines = static_cast<int>(std::floor(band[1] * T + 1e-9) - std::ceil(band[0] * T - 1e-9)) + 1;
  p.random_skip = in.quantity("excitation.skip", dim::time, s.duration / 4);
  if (!(p.random_skip >= 0 && p.random_skip < s.duration))
    in.fail("excitation.skip", "must be >= 0 and below simulation.duration (s): the start-up left out of the response's in-band RMS");
  p.force_time_scale = 1 / band[1];
  // A bound: the RMS force at the worst frequency of the band, times 3 (peak factor).
  for (int k = 0; k <= 200; ++k) {
    const double w = 2 * kPi * (band[0] + (band[1] - band[0]) * k / 200.0);
    p.expected_cavity_speed = std::max(p.expected_cavity_speed, cavity_speed(p, 3 * rms, w));
  }
}

void resolve_excitation(const CaseReader& in, const Scene& s, Primary& p) {
  const std::string kind = in.choice("excitation.kind", {"harmonic", "stepped-sine", "decay", "impulse", "random", "none"}, "harmonic");
  if (kind == "harmonic" || kind == "stepped-sine") {
    p.harmonic = true;
    p.amplitude = in.quantity("excitation.amplitude", dim::force);
    if (!(p.amplitude > 0) || !std::isfinite(p.amplitude)) in.fail("excitation.amplitude", "must be > 0 (N)");
    p.start_steady = in.choice("excitation.start", {"rest", "steady"}, "rest") == "steady";
    std::vector<double> f;
    if (kind == "harmonic") {
      f.push_back(positive(in, "excitation.frequency", dim::frequency, "Hz"));
    } else {
      p.stepped_sine = stepped_sine(in, p, f);
    }
    p.drive_frequency = f.front();
    // The largest bare cavity speed over the swept range, resonances between the points included
    // (the refinement points may drive there).
    double w_at = 0;
    const double X = p.bare_cavity_amplitude_max(p.amplitude, f, w_at);
    p.expected_cavity_speed = X * w_at;
  } else if (kind == "decay") {
    decay_excitation(in, p);
  } else if (kind == "impulse") {
    impulse_excitation(in, p);
  } else if (kind == "random") {
    random_excitation(in, s, p);
  } else {
    p.excitation = make_no_force();
  }
  if (p.harmonic) {
    p.excitation = make_harmonic_force(p.amplitude, p.drive_frequency);
    p.response_frequency = p.drive_frequency;
    if (p.stepped_sine) p.response_frequency = *std::max_element(p.stepped_sine->frequencies.begin(), p.stepped_sine->frequencies.end());
  }
  if (p.response_frequency == 0)  // a blow, random force or none: the first elastic mode rings longest
    for (std::size_t k = 0; k < p.size() && p.response_frequency == 0; ++k)
      if (!p.rigid_body[k]) p.response_frequency = p.natural_frequency[k];
}

}  // namespace

namespace {
// A unit vector normal to d: the coordinate axis least along d, its part along d taken out.
Vec3 any_normal(const Vec3& d) {
  int k = 0;
  d.cwiseAbs().minCoeff(&k);
  const Vec3 u = d.normalized(), e = Vec3::Unit(k);
  return (e - e.dot(u) * u).normalized();
}
}  // namespace

void resolve_primary(const CaseReader& in, Scene& s) {
  std::vector<std::string> names = {"prescribed"};
  for (const auto& k : kPrimaryKinds) names.emplace_back(k.name);
  const std::string kind = in.choice("primary.kind", names, "prescribed");
  if (kind == "prescribed") {
    // [excitation] drives a primary structure; kind = "none" (nothing) is the one allowed without.
    if (in.has("excitation") && in.string("excitation.kind", "harmonic") != "none")
      in.fail("excitation", "drives a primary structure: set primary.kind (sdof, beam, fe-beam, modal), or move the cavity with [cavity.motion]");
    return;
  }
  if (in.string("cavity.motion.kind", "fixed") != "fixed")
    in.fail("cavity.motion.kind", "must be \"fixed\" (or absent) with a primary structure: the structure moves the cavity");
  const Vec3 dir = in.vector("primary.direction", dim::none, Vec3::UnitY());
  if (dir.norm() == 0) in.fail("primary.direction", "must not be the zero vector");
  // An SDOF has no axis of its own: without primary.axis it takes one normal to its direction
  // (the coordinate axis least along it, made normal).
  const Vec3 axis = in.vector("primary.axis", dim::none, kind == "sdof" ? any_normal(dir) : Vec3::UnitX());
  if (axis.norm() == 0) in.fail("primary.axis", "must not be the zero vector");
  if (std::abs(dir.normalized().dot(axis.normalized())) > 1e-9)
    in.fail("primary.axis", in.has("primary.axis") ? "must be normal to primary.direction"
                                                    : "the beam's axis (default [1, 0, 0]) must be normal to primary.direction: give "
                                                      "primary.axis, the direction along the beam");
  Primary p;
  for (const auto& k : kPrimaryKinds)
    if (kind == k.name) p = k.make(in, s, axis.normalized());
  p.direction = dir.normalized();
  p.axis = axis.normalized();
  resolve_excitation(in, s, p);
  s.primary = std::make_shared<const Primary>(std::move(p));
}

}  // namespace bagdem
