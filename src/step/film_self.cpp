// The film against itself (part of the film stage, film.cpp; bag.film.self_contact): each film
// node is the centre of a sphere of radius r_s = Bag::self_radius (by default 0.4 of the film's
// mean edge), which meets the spheres of the nodes that are not its neighbours along an edge. Two
// layers of film then cannot pass through each other: a node would have to pass between three
// nodes of the other layer, whose triangle's circumradius (0.58 of an edge) is below 2 r_s. The
// force is the elastic normal force of the film's law with itself (the interaction of its material
// with itself, contact/law.hpp) at overlap delta = 2 r_s - |x_i - x_j|, R* = r_s / 2: a smooth
// function of the positions, so the pair is conservative. No damping and no friction between the
// layers (the membrane's damping dissipates their motion). Neighbours along an edge are left out,
// so the film still shortens freely in its plane where it wrinkles (the tension field, membrane.hpp);
// a layer's crowded nodes (a crumpled region) meet the spheres of nodes two edges away.
// Bonded-particle membranes use the same spheres for the whole film (docs/bag.md); here they only
// keep the layers apart, and the balls still meet the thin triangulated film.
// The pairs are found at the neighbour build within 2 r_s + skin; they hold while no node moved
// more than skin/2 (the film's candidate lists are renewed then, SurfaceContacts::need_rebuild).
#include <algorithm>
#include <cmath>

#include "bagdem/contact/law.hpp"
#include "film.hpp"

namespace bagdem {

namespace {

// The law's elastic share at overlap delta: energy and force magnitude.
EulerShare self_share(const PairLaw& law, double R, double delta) {
  return visit_law(law.kind, [&](auto L) { return decltype(L)::euler_share(law, R, delta, 1.0); });
}

// fn(i, j, delta, unit normal from j to i) for every pair of the list that overlaps now.
template <class Fn>
void for_each_touching(const Film& film, double r_s, Fn&& fn) {
  const CandidatePairs& c = film.self_pairs;
  const double reach = 2 * r_s;
  for (std::size_t i = 0; i + 1 < c.begin.size(); ++i)
    for (std::uint32_t e = c.begin[i]; e < c.begin[i + 1]; ++e) {
      const std::uint32_t j = c.partner[e];
      const Vec3 d = film.x[i] - film.x[j];
      const double d2 = d.squaredNorm();
      if (!(d2 < reach * reach)) continue;
      const double dist = std::sqrt(d2);
      if (!(dist > 0)) continue;  // coincident nodes: no direction (never at a finite force)
      fn(i, j, reach - dist, Vec3(d / dist));
    }
}

}  // namespace

void build_film_self_pairs(Film& film, const Scene& scene, const std::vector<Vec3>& at_build) {
  if (!scene.bag || !(scene.bag->self_radius > 0)) return;
  film.self_broad->find(at_build, film.self_radii, scene.skin, film.self_found);
  const CandidatePairs& found = film.self_found;
  CandidatePairs& pairs = film.self_pairs;
  const std::size_t nn = at_build.size();
  pairs.begin.assign(1, 0);
  pairs.partner.clear();
  for (std::size_t i = 0; i < nn; ++i) {
    const auto nb_begin = film.neighbour.begin() + film.neighbour_begin[i], nb_end = film.neighbour.begin() + film.neighbour_begin[i + 1];
    for (std::uint32_t e = found.begin[i]; e < found.begin[i + 1]; ++e)
      if (!std::binary_search(nb_begin, nb_end, found.partner[e])) pairs.partner.push_back(found.partner[e]);
    pairs.begin.push_back(static_cast<std::uint32_t>(pairs.partner.size()));
  }
}

void film_self_contacts(const FilmStage& s) {
  const Scene& scene = s.scene;
  if (!(scene.bag->self_radius > 0)) return;
  const Bag& bag = *scene.bag;
  Film& film = s.film;
  const PairLaw& law = scene.laws(bag.material, bag.material);
  const double R = 0.5 * bag.self_radius;
  std::uint64_t touching = 0;
  for_each_touching(film, bag.self_radius, [&](std::size_t i, std::size_t j, double delta, const Vec3& n) {
    const Vec3 F = self_share(law, R, delta).force * n;
    film.f[i] += F;
    film.f[j] -= F;
    ++touching;
  });
  if (touching > 0) ++film.tally.self.steps, film.tally.self.most = std::max(film.tally.self.most, touching);
}

double film_self_energy(const Scene& scene, const Film& film) {
  if (!scene.bag || !(scene.bag->self_radius > 0)) return 0.0;
  const Bag& bag = *scene.bag;
  const PairLaw& law = scene.laws(bag.material, bag.material);
  const double R = 0.5 * bag.self_radius;
  double u = 0;
  for_each_touching(film, bag.self_radius, [&](std::size_t, std::size_t, double delta, const Vec3&) { u += self_share(law, R, delta).energy; });
  return u;
}

}  // namespace bagdem
