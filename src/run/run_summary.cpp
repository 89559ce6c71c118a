// summary.json of a run (run_summary.hpp).
#include "run_summary.hpp"

#include <omp.h>

#include "bagdem/structure/response.hpp"

namespace bagdem {

// summary.json of a complete run: rep's headline figures (the structure's are set here), `psteps`
// the particle-steps of this session, `response` and `response_acc` the structure's response at x_a
// after release, sampled every ds (s).
Summary run_summary(const Scene& scene, const Simulation& sim, RunReport& rep, double psteps, const std::vector<double>& response,
                    const std::vector<double>& response_acc, double ds, bool structure) {
  Summary s;
  s.case_file = scene.case_file, s.particles = sim.particles().size(), s.steps = scene.total_steps();
  if (!scene.more_dampers.empty() || (scene.primary && !structure)) s.damper = scene.damper_name;
  s.dt = scene.dt, s.dt_reason = scene.dt_reason, s.threads = omp_get_max_threads();
  s.wall_time = rep.wall_seconds, s.particle_steps_per_second = rep.wall_seconds > 0 ? psteps / rep.wall_seconds : 0;
  s.ns_per_particle_step = rep.ns_per_particle_step, s.neighbour_builds = sim.neighbour_builds();
  if (scene.models.energy) s.energy = sim.energy(), s.energy_balance_error = rep.energy_balance_error;
  if (rep.bag) {
    const FilmSelfContact c = sim.film_self_contact();
    rep.film_self_steps = c.steps, rep.film_self_pairs_max = c.most, rep.film_wall_stops = sim.film_wall_stops();
    s.bag = SummaryBag{scene.bag->balls, scene.bag->rest.triangles.size(), rep.bag_packing, rep.bag_outer, c.steps, c.most,
                       rep.film_wall_stops};
  }
  if (scene.primary && structure) {
    const Primary& P = *scene.primary;
    const auto& S = sim.structure().scalars;
    rep.structure = true;
    rep.response_rms = rms(response, ds, 0.0);
    rep.acceleration_rms = rms(response_acc, ds, 0.0);
    SummaryStructure st;
    st.kind = P.kind, st.response_at = P.response_at, st.response_rms = rep.response_rms, st.acceleration_rms = rep.acceleration_rms;
    if (P.random_hi > 0) {
      rep.band_response_rms = band_rms(response, ds, P.random_lo, P.random_hi, P.random_skip);
      st.band = SummaryBand{rep.band_response_rms, P.random_lo, P.random_hi, P.random_skip};
    }
    st.work_external = S.work_external, st.work_contents = S.work_contents, st.dissipated = S.dissipated;
    st.energy = sim.structure_energy();
    if (!P.harmonic && response.size() > 8) {
      // Free decay or a blow: the decay of the response (structure/response.hpp, fit_decay).
      st.decay = fit_decay(response, ds);
      rep.decay_time = st.decay->decay_time;
      rep.decay_zeta = st.decay->zeta;
    }
    s.structure = std::move(st);
  }
  s.cycles_measured = rep.cycles;
  if (rep.cycles > 0) s.dissipated_per_cycle = rep.dissipated_per_cycle;
  return s;
}

}  // namespace bagdem
