// The time step. `auto` takes the smallest of
//   (a) timestep_safety x the Rayleigh time of the smallest particle of each material whose contacts
//       follow its moduli (a Hooke pair's spring is the user's: no elastic wave limits it),
//   (b) the contact time at the expected impact speed / steps_per_contact, and for heavily damped
//       contacts (e below ~0.45) the damping time likewise (the law's resolved_step, contact/law.hpp),
//   (c) half the critical step of the stiffest contact (normal, or tangential with the rolling
//       sphere's effective mass 2/7 m*), at the overlap reached at the expected speed;
// an explicit step is refused when above (c)'s critical step unless simulation.force_timestep.
// The expected speed (auto) is 2 x the cavity's peak speed + the free-fall speed over the cavity's
// extent along gravity + the largest initial particle speed.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "bagdem/case/load_case.hpp"
#include "bagdem/contact/hertz_theory.hpp"
#include "bagdem/contact/law.hpp"
#include "bagdem/particles.hpp"

namespace bagdem {

namespace {

// The step limits, each the smallest over what it concerns (s); 1e300 where nothing limits.
struct StepLimits {
  double rayleigh = 1e300, contact = 1e300, critical = 1e300, film = 1e300, structure = 1e300;
  // The largest overlap a contact of the balls reaches at the expected impact speed, over the
  // smaller radius, and the materials of that contact.
  double overlap = 0;
  int overlap_a = -1, overlap_b = -1;
};

// simulation.expected_speed, or (auto) 2 x the cavity's peak speed + the free-fall speed over the
// cavity's extent along gravity + the largest initial particle speed (m/s).
double expected_speed(const CaseReader& in, const Scene& s) {
  double v = 0;
  if (auto given = in.quantity_or_auto("simulation.expected_speed", dim::speed)) {
    if (!(*given > 0)) in.fail("simulation.expected_speed", "must be > 0");
    v = *given;
  } else {
    double height = 0;
    if (s.gravity.norm() > 0) {
      const Vec3 g = s.gravity.normalized();
      const Vec3 ext = s.cavity_hi - s.cavity_lo;
      height = std::abs(g.x()) * ext.x() + std::abs(g.y()) * ext.y() + std::abs(g.z()) * ext.z();
    }
    double v0 = 0;
    for (const auto& p : s.particles) v0 = std::max(v0, p.v.norm());
    const double cavity_speed = s.primary ? s.primary->expected_cavity_speed : s.motion->max_speed();
    v = 2 * cavity_speed + std::sqrt(2 * s.gravity.norm() * height) + v0;
    v = std::max(v, 0.01);
  }
  return v;
}

// The smallest particle radius of each material (0 for a material of no particle).
std::vector<double> smallest_radius(const Scene& s) {
  // Smallest particle of each material, against every material it can touch (particles and walls).
  const int nm = static_cast<int>(s.materials.size());
  std::vector<double> rmin(static_cast<std::size_t>(nm), 0.0);
  for (const auto& p : s.particles) {
    double& r = rmin[static_cast<std::size_t>(p.material)];
    r = r == 0 ? p.radius : std::min(r, p.radius);
  }
  return rmin;
}

// The balls' limits: Rayleigh time, resolved contact time and critical step, against every material
// each can touch (particles and walls).
void contact_limits(const Scene& s, const std::vector<double>& rmin, double v, double per_contact, StepLimits& L) {
  const int nm = static_cast<int>(s.materials.size());
  double &dt_rayleigh = L.rayleigh, &dt_contact = L.contact, &dt_crit = L.critical;
  for (int a = 0; a < nm; ++a) {
    const double r = rmin[static_cast<std::size_t>(a)];
    if (r == 0) continue;
    const Material& ma = s.materials[static_cast<std::size_t>(a)];
    const double rayleigh = hertz::rayleigh_time(r, ma.density, ma.youngs_modulus, ma.poisson_ratio);
    const double m = sphere_mass(ma.density, r);
    for (int b = 0; b < nm; ++b) {
      const bool wall_material =
          std::any_of(s.walls.begin(), s.walls.end(), [&](const Wall& w) { return w.material == b; }) ||
          std::any_of(s.mesh_walls.begin(), s.mesh_walls.end(), [&](const MeshWall& w) { return w.material == b; });
      const bool particle_material = rmin[static_cast<std::size_t>(b)] > 0;
      const PairLaw& law = s.laws(a, b);
      const ContactLawRow& row = contact_law(law.kind);
      if (row.from_moduli && (particle_material || wall_material)) dt_rayleigh = std::min(dt_rayleigh, rayleigh);
      auto consider = [&](double R_eff, double m_eff, double r_small) {
        dt_contact = std::min(dt_contact, row.resolved_step(law, m_eff, R_eff, v, per_contact));
        const double delta = row.max_overlap(law, m_eff, R_eff, v);
        if (delta / r_small > L.overlap) L.overlap = delta / r_small, L.overlap_a = a, L.overlap_b = b;
        const double S_n = row.stiffness(law, R_eff, delta);
        const double zeta = 0.5 * law.damping;  // gamma / (2 sqrt(S m*)) for gamma = damping x sqrt(S m*)
        dt_crit = std::min(dt_crit, hertz::critical_step(std::sqrt(S_n / m_eff), zeta));
        if (s.models.tangential) {
          // The rolling sphere's tangential mass is 2/7 m*, so with gamma_t = gamma_n sqrt(S_t/S_n)
          // the tangential damping ratio is sqrt(3.5) times the normal one.
          const double S_t = row.tangential_stiffness(law, R_eff, delta);
          dt_crit = std::min(dt_crit, hertz::critical_step(std::sqrt(3.5 * S_t / m_eff), std::sqrt(3.5) * zeta));
        }
      };
      if (particle_material) {
        const double rb = rmin[static_cast<std::size_t>(b)];
        const double mb = sphere_mass(s.materials[static_cast<std::size_t>(b)].density, rb);
        consider(r * rb / (r + rb), m * mb / (m + mb), std::min(r, rb));
      }
      if (wall_material) consider(r, m, r);
    }
  }
}

// The bag: the critical steps of its balls against the film (m* down to a film node's mass), of
// the film's nodes against the walls (R* = contact radius), of the membrane's highest frequency,
// and of the strings on their ties. Its light nodes ring at these frequencies for the whole run
// (a ball's contact ends), so `auto` keeps timestep_safety x their smallest, as for the Rayleigh
// time: at half of it (omega dt = 1) the energy budget of an undamped bag drifted by 1e-2, at
// 0.2 x by 4e-5 (tests/test_bag_physics.cpp, BagEnergy).
// A film node is a point: it does not turn, so its tangential mass is its mass, not the rolling
// sphere's 2/7 of it. Against a ball, 1/m_t = 1/m_node + 3.5/m_ball (the ball rolls); against a
// wall m_t = m_node. With gamma_t = damping sqrt(S_t m*) (mindlin.hpp) the tangential damping ratio
// is 0.5 damping sqrt(m*/m_t) (tests/test_film_step.cpp measures both limits).
void film_limits(const Scene& s, const std::vector<double>& rmin, double v, StepLimits& L) {
  const int nm = static_cast<int>(s.materials.size());
  double &dt_film = L.film, &dt_crit = L.critical;
  const Bag& bag = *s.bag;
  const int fm = bag.material;
  const double mn = bag.min_node_mass;
  // Stability only: a film node's own bounce need not be resolved (its mass is a small fraction
  // of a ball's); the ball's contact with the film is resolved by the balls' limits above.
  // m_eff: the normal effective mass; m_t: the tangential one.
  auto consider_film = [&](int a, double R_eff, double m_eff, double m_t) {
    const PairLaw& law = s.laws(a, fm);
    const ContactLawRow& row = contact_law(law.kind);
    const double delta = row.max_overlap(law, m_eff, R_eff, v);
    const double S_n = row.stiffness(law, R_eff, delta);
    dt_film = std::min(dt_film, hertz::critical_step(std::sqrt(S_n / m_eff), 0.5 * law.damping));
    if (s.models.tangential) {
      const double S_t = row.tangential_stiffness(law, R_eff, delta);
      dt_film = std::min(dt_film, hertz::critical_step(std::sqrt(S_t / m_t), std::sqrt(m_eff / m_t) * 0.5 * law.damping));
    }
  };
  for (int a = 0; a < nm; ++a) {
    const double r = rmin[static_cast<std::size_t>(a)];
    if (r == 0) continue;
    const double m = sphere_mass(s.materials[static_cast<std::size_t>(a)].density, r);
    const double ball_t = s.models.rotation ? 2.0 / 7.0 * m : m;  // the ball's own tangential mass
    consider_film(a, r, m * mn / (m + mn), mn * ball_t / (mn + ball_t));
  }
  for (const Wall& w : s.walls) consider_film(w.material, bag.contact_radius, mn, mn);
  for (const MeshWall& w : s.mesh_walls) consider_film(w.material, bag.contact_radius, mn, mn);
  if (bag.self_radius > 0) consider_film(bag.material, 0.5 * bag.self_radius, 0.5 * mn, mn);  // node against node
  // Membrane (Kelvin-Voigt damping ratio zeta at its top frequency) and strings on their ties.
  dt_film = std::min(dt_film, hertz::critical_step(bag.max_frequency, bag.damping_ratio));
  for (const BagString& st : bag.strings) {
    const double m_tie = mn * static_cast<double>(st.nodes.size());
    const double w = std::sqrt(st.stiffness / m_tie), zeta = st.damping / (2 * std::sqrt(st.stiffness * m_tie));
    dt_film = std::min(dt_film, hertz::critical_step(w, zeta));  // spring and damper on the tie
  }
  dt_crit = std::min(dt_crit, dt_film);
}

// The primary structure: velocity Verlet is stable for omega_max dt < 2 and its frequency error
// is (omega dt)^2 / 24; `auto` keeps omega_max dt <= 0.2 (0.17% at the highest mode kept).
void structure_limits(const Scene& s, StepLimits& L) {
  double &dt_structure = L.structure, &dt_crit = L.critical;
  const double w = s.primary->omega_max();
  if (w > 0) {
    dt_structure = 0.2 / w;
    dt_crit = std::min(dt_crit, 2.0 / w);
  }
  // The force itself: 20 steps over a hammer blow, 20 per period of the highest random line.
  if (s.primary->force_time_scale > 0) dt_structure = std::min(dt_structure, s.primary->force_time_scale / 20);
}

// The step: explicit (refused above the critical step unless forced; a warning when coarser than
// the contact's resolution) or auto (the smallest limit); why it is what it is goes to `why`.
void choose_step(const CaseReader& in, Scene& s, const StepLimits& L, double safety, double per_contact, double v,
                 std::ostringstream& why) {
  const double dt_rayleigh = L.rayleigh, dt_contact = L.contact, dt_crit = L.critical, dt_film = L.film,
               dt_structure = L.structure;
  const bool forced = in.boolean("simulation.force_timestep", false);  // read whether or not it is needed
  if (auto given = in.quantity_or_auto("simulation.timestep", dim::time)) {
    s.dt = *given;
    if (!(s.dt > 0)) in.fail("simulation.timestep", "must be > 0 or \"auto\"");
    if (s.dt > dt_crit && !forced) {
      std::ostringstream m;
      m << "is above the critical step " << dt_crit << " s of the stiffest contact (or the primary structure's highest mode) at the expected "
        << "impact speed " << v << " m/s; the run would be unstable. Use \"auto\", a step below "
        << dt_crit << " s, or set simulation.force_timestep = true";
      in.fail("simulation.timestep", m.str());
    }
    if (s.dt > dt_crit) {
      std::ostringstream w;
      w << "simulation.timestep = " << s.dt << " s is above the critical step " << dt_crit
        << " s (simulation.force_timestep = true): the integration may diverge, and the guards then stop the run";
      s.warnings.push_back(w.str());
    }
    why << "explicit";
    if (s.dt > dt_contact * 1.0000001) {
      std::ostringstream w;
      w << "simulation.timestep = " << s.dt << " s is coarser than the step that resolves the stiffest contact ("
        << dt_contact << " s: the contact time / " << per_contact
        << ", and the damping time when e is low); the restitution obtained may differ from the one requested "
           "(more so at low e). Use \"auto\" or a step of at most "
        << dt_contact << " s for exact restitution.";
      s.warnings.push_back(w.str());
    }
  } else {
    const double a = safety * dt_rayleigh, b = dt_contact, c = 0.5 * dt_crit, f = safety * dt_film;
    s.dt = std::min({a, b, c, f, dt_structure});
    why << "auto: min of ";
    if (dt_rayleigh < 1e300) why << safety << " x Rayleigh " << dt_rayleigh << " s = " << a << " s";
    else why << "no Rayleigh limit (no Hertz-Mindlin pair)";
    why << ", contact time (or damping time when e is low) / " << per_contact << " = " << b
        << " s, half the critical step = " << c << " s";
    if (s.bag) why << ", " << safety << " x the film's critical step " << dt_film << " s = " << f << " s";
    if (s.primary) why << ", the structure (0.2 / its highest circular frequency, 1/20 of the force's time scale) " << dt_structure << " s";
    why << " -> " << (s.dt == a ? "Rayleigh" : s.dt == b ? "contact time" : s.dt == c ? "critical step" : s.dt == f ? "film" : "structure")
        << " limits";
  }
}

// A contact that would overlap more than the guard allows (simulation.max_overlap) at the expected
// impact speed: the run is likely to stop there. A warning, not a refusal: the expected speed is an
// upper estimate (2 x the cavity's peak speed + free fall). Names the key that stiffens the contact.
void overlap_warning(const CaseReader& in, Scene& s, const StepLimits& L, double v) {
  if (L.overlap <= s.max_overlap_fraction || L.overlap_a < 0) return;
  const std::string& A = s.materials[static_cast<std::size_t>(L.overlap_a)].name;
  const std::string& B = s.materials[static_cast<std::size_t>(L.overlap_b)].name;
  std::string key;
  if (contact_law(s.laws(L.overlap_a, L.overlap_b).kind).from_moduli) {
    const bool a_softer = s.materials[static_cast<std::size_t>(L.overlap_a)].youngs_modulus <= s.materials[static_cast<std::size_t>(L.overlap_b)].youngs_modulus;
    key = "materials." + (a_softer ? A : B) + ".youngs_modulus";
  } else {
    key = "interactions.default.stiffness";
    for (const std::string& pair : {A + "-" + B, B + "-" + A})
      if (in.has("interactions." + pair + ".stiffness")) key = "interactions." + pair + ".stiffness";
  }
  std::ostringstream w;
  w << "at the expected impact speed " << v << " m/s a " << A << "-" << B << " contact would overlap " << 100 * L.overlap
    << "% of the smaller radius, above the guard's " << 100 * s.max_overlap_fraction
    << "% (simulation.max_overlap): the run may stop there. Raise " << key
    << ", or give simulation.expected_speed if the impacts are slower";
  s.warnings.push_back(w.str());
}

// The drive and the force must be resolved by the chosen step.
void check_drive(const CaseReader& in, Scene& s) {
  if (s.primary) {
    // The drive and the force must be resolved by the chosen step.
    if (s.primary->harmonic) {
      double f_max = s.primary->drive_frequency;
      if (s.primary->stepped_sine)
        for (double f : s.primary->stepped_sine->frequencies) f_max = std::max(f_max, f);
      if (f_max * s.dt > 1.0 / 8) {
        // response.cpp drives at 1 / (N dt) with N >= 8: a faster drive would silently be another one.
        std::string key = "excitation.frequency";
        for (const char* k : {"excitation.frequency", "excitation.frequencies", "excitation.band", "excitation.around_modes"})
          if (in.has(k)) {
            key = k;
            break;
          }
        std::ostringstream m;
        m << "asks for a drive at up to " << f_max << " Hz, only " << 1 / (f_max * s.dt) << " steps per cycle at dt = " << s.dt
          << " s; a drive needs at least 8 steps per cycle: give at most " << 1 / (8 * s.dt) << " Hz, or a smaller simulation.timestep";
        in.fail(key, m.str());
      }
      if (f_max * s.dt > 1.0 / 20) {
        std::ostringstream w;
        w << "the drive frequency " << f_max << " Hz has only " << 1 / (f_max * s.dt) << " steps per cycle at dt = "
          << s.dt << " s; it is driven at 1 / (N dt) with N whole (at least 8): reduce simulation.timestep";
        s.warnings.push_back(w.str());
      }
    }
    if (s.primary->force_time_scale > 0 && s.dt > s.primary->force_time_scale / 20) {
      std::ostringstream w;
      w << "simulation.timestep = " << s.dt << " s resolves the force's time scale " << s.primary->force_time_scale
        << " s (a blow's duration, or the highest random line's period) with fewer than 20 steps; use \"auto\" or a step of at most "
        << s.primary->force_time_scale / 20 << " s";
      s.warnings.push_back(w.str());
    }
  }
}

}  // namespace

void resolve_timestep(const CaseReader& in, Scene& s) {
  const double safety = in.quantity("simulation.timestep_safety", dim::none, 0.2);
  if (!(safety > 0 && safety <= 1)) in.fail("simulation.timestep_safety", "must be in (0, 1]");
  const double per_contact = in.quantity("simulation.steps_per_contact", dim::none, 40);
  if (!(per_contact >= 10)) in.fail("simulation.steps_per_contact", "must be >= 10 (30 or more recommended)");
  const double v = expected_speed(in, s);
  s.expected_speed = v;

  const std::vector<double> rmin = smallest_radius(s);
  StepLimits L;
  contact_limits(s, rmin, v, per_contact, L);
  if (s.bag) film_limits(s, rmin, v, L);
  if (s.primary) structure_limits(s, L);
  s.dt_critical = L.critical;

  std::ostringstream why;
  choose_step(in, s, L, safety, per_contact, v, why);
  check_drive(in, s);
  overlap_warning(in, s, L, v);
  why << "; expected impact speed " << v << " m/s; critical step " << L.critical << " s";
  s.dt_reason = why.str();
}

}  // namespace bagdem
