// `bagdem check`: the resolved scene in words — what is modelled and what is switched off, N, dt and
// how it was chosen, steps, memory estimate.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <iomanip>
#include <sstream>

#include "bagdem/case/load_case.hpp"
#include "bagdem/contact/law.hpp"
#include "bagdem/contact/mindlin.hpp"
#include "bagdem/contact/rolling.hpp"
#include "bagdem/particles.hpp"
#include "bagdem/structure/excitation.hpp"

namespace bagdem {

namespace {

const char* on(bool b) { return b ? "on " : "off"; }

// The bag: its shape, fill, film and strings (rmin: the smallest ball radius).
void describe_bag(std::ostream& o, const Scene& s, double rmin) {
  const Bag& b = *s.bag;
    const double V = enclosed_volume(b.rest, b.rest.vertices);
    const double film_mass = b.film_mass();
    o << "bag         " << b.shape << ", " << b.balls << " balls (" << b.source << "), outer " << 1e3 * b.size.x()
      << " x " << 1e3 * b.size.y() << " x " << 1e3 * b.size.z() << " mm " << (b.shrink < 1 ? "as made" : "at rest") << ", volume "
      << V * 1e6 << " cm^3, fill fraction " << b.fill_fraction;
    if (b.shrink < 1)
      o << " (pulled tight, key bag.film.shrink: the volume and fill are the unstretched film's, " << b.shrink << " of its made size)";
    o << "\n";
    double ball_mass = 0;
    for (std::size_t k = b.ball_first; k < b.ball_first + b.balls; ++k) ball_mass += sphere_mass(s.materials[static_cast<std::size_t>(s.particles[k].material)].density, s.particles[k].radius);
    o << "            balls " << ball_mass << " kg";
    if (s.primary) o << " = " << ball_mass / s.primary->structure_mass << " of the structure's mass (whole balls)";
    o << "\n"
      << "film        " << s.materials[static_cast<std::size_t>(b.material)].name << ", thickness " << b.film.thickness
      << " m, mass " << film_mass << " kg; resolution " << b.rest.triangles.size() << " triangles, "
      << b.rest.vertices.size() << " nodes, mean edge " << b.mean_edge << " m (" << b.mean_edge / (2 * rmin)
      << " ball diameters; key bag.triangles)\n"
      << "            tension field " << on(b.film.tension_field) << ", bending D " << b.film.bending_stiffness
      << " N m (" << (b.film.bending_model == BendingModel::Quadratic ? "quadratic, flat at rest" : "hinges, the rest shape's angles")
      << "; key bag.film.bending_model), damping ratio " << b.damping_ratio << " (Kelvin-Voigt time " << b.film.damping_time
      << " s), node mass x " << b.mass_scaling << ", film-wall contact radius " << b.contact_radius << " m\n"
      << "            film-film contact ";
    if (b.self_radius > 0)
      o << "on: node spheres of radius " << b.self_radius << " m (" << b.self_radius / b.mean_edge
        << " mean edges) against the nodes not along an edge\n";
    else
      o << "off (key bag.film.self_contact): the film may pass through itself\n";
    o << "            highest membrane frequency " << b.max_frequency / (2 * std::numbers::pi)
      << " Hz: critical step " << 2 / b.max_frequency << " s\n"
      << "            bending every " << b.bending_interval << " step(s) (key bag.film.bending_interval; its highest frequency "
      << b.bending_frequency / (2 * std::numbers::pi) << " Hz)\n";
    for (const BagString& st : b.strings)
      o << "string      " << st.name << ": " << st.nodes.size() << " tie nodes, anchor [" << st.anchor.transpose()
        << "] m, k " << st.stiffness << " N/m, c " << st.damping << " N s/m, rest length " << st.rest_length << " m\n";
}

// The primary structure, its excitation and, for a sweep, how a point is judged steady.
void describe_primary(std::ostream& o, const Scene& s) {
  const Primary& P = *s.primary;
    o << "primary     " << P.description << "\n"
      << "            moves along [" << P.direction.transpose() << "]";
    if (P.kind == "beam" || P.kind == "fe-beam")
      o << ", axis [" << P.axis.transpose() << "], cavity at x_b = " << P.attach << " m, force at x_f = " << P.force_at
        << " m, response at x_a = " << P.response_at << " m";
    else if (P.kind == "modal")
      o << ", axis [" << P.axis.transpose() << "] (the table's shapes give the cavity, force and response points)";
    o << "; structure mass " << P.structure_mass << " kg" << (s.settle > 0 ? "; held while settling" : "") << "\n";
    if (P.kind != "sdof") {
      o << "            damping ratios";
      for (std::size_t k = 0; k < P.size(); ++k) o << (k ? ", " : " ") << P.dof_names[k] << " " << P.damping_ratio[k];
      o << "\n";
    }
    o << "excitation  " << (P.stepped_sine ? "stepped-sine sweep, " + std::to_string(P.stepped_sine->frequencies.size()) + " frequencies from " +
                                          std::to_string(P.stepped_sine->frequencies.front()) + " Hz; " : std::string())
      << (P.excitation ? P.excitation->describe() : std::string("none"))
      << (P.harmonic ? (P.start_steady ? " (starts in the bare steady state)" : " (starts from rest)") : "")
      << "; expected cavity speed " << P.expected_cavity_speed << " m/s\n";
    if (const auto& sw = P.stepped_sine) {
      const std::size_t K = sw->half_window();
      o << "            each point: steady when the mean response of its last " << K << " cycles is within "
        << 100 * sw->tolerance << "% of the " << K << " before or within their scatter (a 5% two-sample test), and its "
        << "energy balances within 1% (at least " << sw->least_cycles() << ", at most " << sw->max_cycles
        << " cycles), reduced over those " << 2 * K << " cycles with 95% intervals\n";
      const std::size_t chains = std::min(sw->chains, sw->frequencies.size());
      o << "            " << chains << (chains == 1 ? " chain: each point from the state of the one before"
                                                    : " chains side by side, each a simulation from the settled contents "
                                                      "through its block of the frequencies (excitation.chains)")
        << (sw->predict ? "; each point after a chain's first starts from its steady state predicted with the contents "
                          "measured before (excitation.predict)"
                        : "")
        << "\n";
    }
    if (P.harmonic) {
      // The bare structure's largest cavity amplitude over the drive frequencies, and Gamma.
      const std::vector<double> f = P.stepped_sine ? P.stepped_sine->frequencies : std::vector<double>{P.drive_frequency};
      double w = 0;
      const double X = P.bare_cavity_amplitude_max(P.amplitude, f, w);
      o << "            bare structure: cavity amplitude up to " << X << " m at " << w / (2 * std::numbers::pi)
        << " Hz (Gamma = X w^2 / g = " << (s.gravity.norm() > 0 ? X * w * w / s.gravity.norm() : 0.0)
        << ") over the swept range\n";
    }
}

// What is modelled, the neighbour search, the step, the run's length, its outputs and guards.
void describe_numerics(std::ostream& o, const Scene& s) {
  bool hertz = false, hooke = false;
  for (const PairLaw& l : s.laws.laws) (l.kind == LawKind::Hooke ? hooke : hertz) = true;
  if (hertz) o << "modelled    normal Hertz + restitution damping (force clamped at zero): on\n";
  if (hooke) o << (hertz ? "            " : "modelled    ") << "normal linear spring-dashpot (hooke, not clamped):   on\n";
  o << "            tangential spring, history, Coulomb cap:               " << on(s.models.tangential)
    << (s.models.tangential ? "" : " (no pair has friction)") << "\n"
    << "            rolling resistance (EPSD2):                             " << on(s.models.rolling)
    << (s.models.rolling ? "" : " (no pair has rolling friction)") << "\n"
    << "            rotation integration:                                   " << on(s.models.rotation)
    << (s.models.rotation ? "" : " (nothing creates torque)") << "\n"
    << "            gravity:                                                " << on(s.models.gravity) << "\n"
    << "            energy budget tallies:                                  " << on(s.models.energy) << "\n";
  o << "neighbours  " << s.broad_phase << ", Verlet skin " << s.skin << " m\n";
  o << "time step   " << s.dt << " s (" << s.dt_reason << ")\n";
  o << "duration    settle " << s.settle << " s + measured " << s.duration << " s = " << s.total_steps()
    << " steps\n";
  o << "output      frames every " << s.output.frame_interval << " s, cavity samples every "
    << s.output.cavity_interval << " s, energy every " << s.output.energy_interval << " s, checkpoints "
    << (s.primary && s.primary->stepped_sine ? std::string("after settling and each point (a sweep)")
        : s.output.checkpoint_interval > 0 ? "every " + std::to_string(s.output.checkpoint_interval) + " s"
                                           : std::string("off"))
    << "; on SIGINT/SIGTERM\n";
  o << "guards      overlap above " << 100 * s.max_overlap_fraction
    << "% of a radius, NaN, or a particle outside the cavity stops the run";
  if (s.models.energy && s.max_energy_error > 0) o << "; so does an energy budget off by " << 100 * s.max_energy_error << "% of its scale";
  if (s.bag)
    o << "; the film's nodes are stopped at " << 100 * s.max_overlap_fraction << "% of bag.film.contact_radius into a cavity wall "
      << "(the walls' stop; an STL wall's depth stops the run)";
  o << "\n";
}

// The memory of the step and the size of results.h5, estimated.
void describe_memory(std::ostream& o, const Scene& s) {
  const std::size_t n = s.particles.size();
  // Memory: hot particle arrays + tallies + ~12 candidate pairs per particle with their buffers.
  const double per_particle = 5 * 24 + 4 * 8 + 4 + 4 * 24 + 4 * 8 + 24 +
                              s.walls.size() * ((s.models.tangential ? sizeof(TangentialHistory) : 0) +
                                                (s.models.rolling ? sizeof(RollingHistory) : 0));
  const double per_pair = 4 + 4 + 3 * 24 + (s.models.energy ? 24 : 0) + 8 +
                          (s.models.tangential ? sizeof(TangentialHistory) : 0) +
                          (s.models.rolling ? sizeof(RollingHistory) : 0);
  double mem = static_cast<double>(n) * (per_particle + 12 * per_pair);
  if (s.bag || !s.mesh_walls.empty()) {
    // Triangle contacts: 8 slots per ball; the film: node arrays, per-triangle and per-hinge records.
    mem += static_cast<double>(n) * 8 * (sizeof(TangentialHistory) + sizeof(RollingHistory) + 120);
    if (s.bag)
      mem += static_cast<double>(s.bag->rest.vertices.size()) * 12 * 24 +
             static_cast<double>(s.bag->rest.triangles.size()) * (2 * 72 + 120) +
             static_cast<double>(s.bag->rest.edge_vertices.size()) * (96 + 48);
  }
  const double frames = std::floor((s.settle + s.duration) / s.output.frame_interval) + 1;
  o << "memory      about " << mem / 1048576 << " MiB in the step; results.h5 about "
    << (frames * static_cast<double>(n) * 72 + frames * static_cast<double>(s.bag ? s.bag->rest.vertices.size() : 0) * 24 +
        (s.settle + s.duration) / s.output.cavity_interval * 120) / 1048576
    << " MiB\n";
}

// The damper's contents and cavity: its balls, cavity, bag and STL walls.
void describe_contents(std::ostream& o, const Scene& s) {
  double rmin = 1e300, rmax = 0, mass = 0;
  for (const auto& p : s.particles) {
    rmin = std::min(rmin, p.radius);
    rmax = std::max(rmax, p.radius);
    mass += sphere_mass(s.materials[static_cast<std::size_t>(p.material)].density, p.radius);
  }
  const std::size_t n = s.particles.size();
  o << "particles   N = " << n << ", diameter " << 2 * rmin << " .. " << 2 * rmax << " m, total mass "
    << mass << " kg\n";
  o << "cavity      " << s.cavity_kind << " (" << s.walls.size() << " walls), bounds [" << s.cavity_lo.transpose()
    << "] .. [" << s.cavity_hi.transpose() << "] m\n";
  if (s.bag) describe_bag(o, s, rmin);
  if (!s.mesh_walls.empty())
    for (const MeshWall& w : s.mesh_walls)
      o << "stl wall    " << w.name << ": " << w.mesh.triangles.size() << " triangles, " << (w.mesh.closed() ? "closed" : "open") << "\n";
}

}  // namespace

std::string describe_scene(const Scene& s) {
  std::ostringstream o;
  o << std::setprecision(4);
  o << "case        " << s.case_file << "\n";
  for (const auto& m : s.materials)
    o << "material    " << m.name << ": density " << m.density << " kg/m^3, E " << m.youngs_modulus
      << " Pa, nu " << m.poisson_ratio << "\n";
  for (int a = 0; a < s.laws.n; ++a)
    for (int b = a; b < s.laws.n; ++b) {
      const PairLaw& l = s.laws(a, b);
      o << "pair        " << s.materials[static_cast<std::size_t>(a)].name << "-"
        << s.materials[static_cast<std::size_t>(b)].name << ": " << contact_law(l.kind).name << ", e " << l.restitution;
      if (l.kind == LawKind::Hooke)
        o << " (damping ratio " << 0.5 * l.damping << "), mu_s " << l.friction << ", mu_r " << l.rolling << ", k_n "
          << l.stiffness << " N/m, k_t/k_n " << l.tangential_ratio * l.tangential_ratio << "\n";
      else
        o << " (clamped-law |beta| " << l.damping / (2 * std::sqrt(5.0 / 6.0)) << "), mu_s " << l.friction << ", mu_r "
          << l.rolling << ", E* " << l.E_star << " Pa, G* " << l.G_star << " Pa\n";
    }
  describe_contents(o, s);
  if (!s.more_dampers.empty()) {
    o << "dampers     " << 1 + s.more_dampers.size() << " on the structure ([[dampers]]): " << s.damper_name << " (the case's own), attached at "
      << s.primary->attach << " m, cavity mass " << s.primary->cavity_mass << " kg; the others below\n";
    for (const Damper& d : s.more_dampers) {
      const Primary& P = *d.scene->primary;
      o << "damper      " << d.name << ": attached at " << P.attach << " m, cavity mass " << P.cavity_mass << " kg, axis [" << P.axis.transpose()
        << "], direction [" << P.direction.transpose() << "]" << (P.follow_slope ? ", turns with the slope" : "") << "\n";
      describe_contents(o, *d.scene);
    }
  }
  if (s.primary) describe_primary(o, s);
  else o << "motion      " << s.motion->describe() << (s.settle > 0 ? " (starts after settling)" : "") << "\n";
  o << "gravity     [" << s.gravity.transpose() << "] m/s^2\n";
  describe_numerics(o, s);
  describe_memory(o, s);
  return o.str();
}

std::vector<std::string> scene_record(const Scene& s) {
  std::vector<std::string> lines;
  std::istringstream in(describe_scene(s));
  for (std::string line; std::getline(in, line);)
    if (line.rfind("case ", 0) != 0 && line.rfind("memory ", 0) != 0) lines.push_back(line);
  return lines;
}

std::string scene_difference(const std::vector<std::string>& was, const std::vector<std::string>& now) {
  const std::size_t n = std::max(was.size(), now.size());
  auto line = [](const std::vector<std::string>& v, std::size_t k) { return k < v.size() ? "'" + v[k] + "'" : std::string("(no line)"); };
  for (std::size_t k = 0; k < n; ++k)
    if (k >= was.size() || k >= now.size() || was[k] != now[k]) return "was " + line(was, k) + ", now " + line(now, k);
  return "";
}

}  // namespace bagdem
