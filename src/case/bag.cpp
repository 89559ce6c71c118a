// [bag] -> Bag: the film's shape and resolution, its membrane and contact parameters, the balls it
// holds (placed on an FCC lattice inside the film, lowest first along gravity), and the strings.
// Or, with bag.from, a settled bag saved by an earlier run (io/bag_file.hpp). Schema:
// docs/case-schema.md, section [bag].
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <random>
#include <sstream>

#include "bagdem/case/load_case.hpp"
#include "bagdem/contact/sphere_triangle.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/bag_file.hpp"
#include "bagdem/mesh/shapes.hpp"
#include "bagdem/neighbour/broad_phase.hpp"
#include "bagdem/neighbour/mesh_candidates.hpp"
#include "bagdem/particles.hpp"
#include "tight_bag.hpp"

namespace bagdem {
namespace {

constexpr double kPi = std::numbers::pi;

int material_index(const CaseReader& in, const std::string& key, const std::vector<std::string>& names) {
  const std::string m = in.string(key);
  const auto it = std::find(names.begin(), names.end(), m);
  if (it == names.end()) in.fail(key, "must name a material defined under [materials]");
  return static_cast<int>(it - names.begin());
}

Vec3 unit_vector(const CaseReader& in, const std::string& key, const Vec3& fallback) {
  const Vec3 v = in.vector(key, dim::none, fallback);
  if (!(v.norm() > 0)) in.fail(key, "must be a non-zero vector");
  return v.normalized();
}

// Volume of the superellipsoid |x/a|^p + |y/b|^p + |z/c|^p <= 1.
double superellipsoid_volume(const Vec3& semi, double p) {
  const double g = std::tgamma(1 + 1 / p);
  return 8 * semi.x() * semi.y() * semi.z() * g * g * g / std::tgamma(1 + 3 / p);
}

// Number of balls asked for: count, total mass, or mass ratio against the primary's mass.
std::size_t ball_count(const CaseReader& in, double ball_mass, double primary_mass) {
  const bool by_count = in.has("bag.balls.count"), by_mass = in.has("bag.balls.mass"),
             by_ratio = in.has("bag.balls.mass_ratio");
  if (by_count + by_mass + by_ratio != 1)
    in.fail("bag.balls", "needs exactly one of count, mass, or mass_ratio (of [primary]'s mass, or of primary_mass)");
  if (by_count) {
    const long long n = in.integer("bag.balls.count", 0);
    if (n < 1 || n > 10000000) in.fail("bag.balls.count", "must be in [1, 1e7]");
    return static_cast<std::size_t>(n);
  }
  double mass = 0;
  std::string key;
  if (by_mass) {
    key = "bag.balls.mass";
    mass = in.quantity(key, dim::mass);
  } else {
    key = "bag.balls.mass_ratio";
    const double ratio = in.quantity(key, dim::none);
    // The primary structure's own mass, unless given (a prescribed-motion case has no structure).
    const double primary = primary_mass > 0 && !in.has("bag.balls.primary_mass")
                               ? primary_mass
                               : in.quantity("bag.balls.primary_mass", dim::mass);
    if (!(ratio > 0)) in.fail(key, "must be > 0 (ball mass / primary mass)");
    if (!(primary > 0)) in.fail("bag.balls.primary_mass", "must be > 0");
    mass = ratio * primary;
  }
  const double n = std::round(mass / ball_mass);
  if (!(n >= 1)) in.fail(key, "is less than one ball (" + std::to_string(ball_mass) + " kg each)");
  return static_cast<std::size_t>(n);
}

// The sites inside the film and clear of it: no triangle within r + reach (+1% of d).
std::vector<Vec3> clear_of_film(const TriangleMesh& mesh, const std::vector<Vec3>& sites, double r, double reach) {
  const double clear = r + reach + 0.02 * r;
  MeshCandidates near;
  find_mesh_candidates(mesh, mesh.vertices, sites, std::vector<double>(sites.size(), clear), Vec3::Zero(), 0.0, 0.0, near);
  std::vector<Vec3> inside;
  for (std::size_t s = 0; s < sites.size(); ++s)
    if (near.begin[s] == near.begin[s + 1] && winding_number(mesh, mesh.vertices, sites[s]) > 0.5)
      inside.push_back(sites[s]);
  return inside;
}

// One ball's site: the centre moved by an offset drawn (seed) within half the ball's radius along
// each axis, the first of 64 draws clear of the film, each draw 10% smaller than the one before
// (a ball hardly smaller than its bag takes one of a few um; the centre when none is clear), so
// that the starts of an ensemble differ as a bed's do.
std::vector<Vec3> single_site(const TriangleMesh& mesh, const Vec3& centre, double r, double reach, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-0.5 * r, 0.5 * r);
  std::vector<Vec3> tries;
  double scale = 1;
  for (int k = 0; k < 64; ++k, scale *= 0.9) tries.push_back(centre + scale * draw_vec3([&] { return u(rng); }));
  const std::vector<Vec3> clear = clear_of_film(mesh, tries, r, reach);
  if (!clear.empty()) return {clear.front()};
  return clear_of_film(mesh, {centre}, r, reach);
}

// FCC lattice sites strictly inside the film at rest, clear of it by the ball radius plus half the
// thickness (and 1% of the diameter), lowest first along gravity (nearest the centre without it).
std::vector<Vec3> lattice_sites(const TriangleMesh& mesh, const Vec3& centre, double r, double reach, const Vec3& gravity,
                                std::uint64_t seed) {
  Vec3 lo = mesh.vertices[0], hi = lo;
  for (const Vec3& v : mesh.vertices) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  const double a = 2 * r * 1.001 * std::sqrt(2.0);  // cubic cell of FCC with neighbour distance 2r x 1.001
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, a);
  const Vec3 origin = lo + draw_vec3([&] { return u(rng); });
  const Vec3 basis[4] = {Vec3(0, 0, 0), Vec3(0.5, 0.5, 0), Vec3(0.5, 0, 0.5), Vec3(0, 0.5, 0.5)};
  std::vector<Vec3> sites;
  const Vec3 n_cells = ((hi - lo) / a).array().ceil() + 1;
  for (int i = -1; i < n_cells.x(); ++i)
    for (int j = -1; j < n_cells.y(); ++j)
      for (int k = -1; k < n_cells.z(); ++k)
        for (const Vec3& b : basis) {
          const Vec3 x = origin + a * (Vec3(i, j, k) + b);
          if ((x - lo).minCoeff() > r && (hi - x).minCoeff() > r) sites.push_back(x);
        }
  std::vector<Vec3> inside = clear_of_film(mesh, sites, r, reach);
  const Vec3 down = gravity.norm() > 0 ? Vec3(gravity.normalized()) : Vec3::Zero();
  std::stable_sort(inside.begin(), inside.end(), [&](const Vec3& p, const Vec3& q) {
    if (down.norm() > 0) {
      const double hp = std::round(p.dot(down) / (1e-6 * r)), hq = std::round(q.dot(down) / (1e-6 * r));
      if (hp != hq) return hp > hq;  // lower first
    }
    return (p - centre).squaredNorm() < (q - centre).squaredNorm();
  });
  return inside;
}

void resolve_strings(const CaseReader& in, Bag& bag, const Scene& s) {
  const std::size_t n = in.array_size("bag.strings");
  const double half_length = 0.5 * bag.size.x();
  const double thickness_radius = 0.5 * std::min(bag.size.y(), bag.size.z());
  for (std::size_t k = 0; k < n; ++k) {
    const std::string key = "bag.strings." + std::to_string(k);
    BagString st;
    st.name = key;
    // Where it is tied: "head" / "tail" (the ends of the bag's axis) or a point near the bag.
    Vec3 centre(0, 0, 0);
    for (const Vec3& v : bag.rest.vertices) centre += v;
    centre /= static_cast<double>(bag.rest.vertices.size());
    Vec3 at;
    if (in.is_string(key + ".at")) {
      const std::string where = in.choice(key + ".at", {"head", "tail"}, "head");
      at = centre + (where == "head" ? 1.0 : -1.0) * half_length * bag.axis;
    } else {
      at = in.vector(key + ".at", dim::length);
    }
    std::uint32_t nearest = 0;
    for (std::uint32_t v = 0; v < bag.rest.vertices.size(); ++v)
      if ((bag.rest.vertices[v] - at).squaredNorm() < (bag.rest.vertices[nearest] - at).squaredNorm()) nearest = v;
    const double tie = in.quantity_or_auto(key + ".tie_radius", dim::length).value_or(0.3 * thickness_radius);
    if (!(tie >= 0)) in.fail(key + ".tie_radius", "must be >= 0 or \"auto\"");
    for (std::uint32_t v = 0; v < bag.rest.vertices.size(); ++v)
      if ((bag.rest.vertices[v] - bag.rest.vertices[nearest]).norm() <= tie) st.nodes.push_back(v);
    st.anchor = in.vector(key + ".anchor", dim::length);
    st.stiffness = in.quantity(key + ".stiffness", dim::stiffness);
    st.damping = in.quantity(key + ".damping", dim::damping, 0.0);
    if (!(st.stiffness > 0)) in.fail(key + ".stiffness", "must be > 0 (N/m)");
    if (!(st.damping >= 0)) in.fail(key + ".damping", "must be >= 0 (N s/m)");
    Vec3 tie_centre(0, 0, 0);
    for (std::uint32_t v : st.nodes) tie_centre += bag.x0[v];
    tie_centre /= static_cast<double>(st.nodes.size());
    const double initial = (st.anchor + s.motion->at(0.0).position - tie_centre).norm();
    st.rest_length = in.quantity_or_auto(key + ".rest_length", dim::length).value_or(initial);
    if (!(st.rest_length >= 0)) in.fail(key + ".rest_length", "must be >= 0 or \"auto\" (the initial distance)");
    bag.strings.push_back(std::move(st));
  }
}

// [bag.film]: the film's material, thickness, bending, damping and mass scaling.
void read_film(const CaseReader& in, const Scene& s, const std::vector<std::string>& names, Bag& b) {
  b.material = material_index(in, "bag.film.material", names);
  const Material& fm = s.materials[static_cast<std::size_t>(b.material)];
  b.film.youngs_modulus = fm.youngs_modulus;
  b.film.poisson_ratio = fm.poisson_ratio;
  b.film.density = fm.density;
  b.film.thickness = in.quantity("bag.film.thickness", dim::length);
  if (!(b.film.thickness > 0)) in.fail("bag.film.thickness", "must be > 0 (m)");
  b.film.tension_field = in.boolean("bag.film.tension_field", true);
  const double bending = in.quantity("bag.film.bending", dim::none, 1.0);
  if (!(bending >= 0)) in.fail("bag.film.bending", "must be >= 0 (a factor on the plate stiffness E t^3 / (12 (1 - nu^2)))");
  const double t = b.film.thickness, nu = b.film.poisson_ratio;
  b.film.bending_stiffness = bending * b.film.youngs_modulus * t * t * t / (12 * (1 - nu * nu));
  b.film.bending_model = in.choice("bag.film.bending_model", {"hinge", "quadratic"}, "hinge") == "quadratic" ? BendingModel::Quadratic
                                                                                                      : BendingModel::Hinge;
  b.damping_ratio = in.quantity("bag.film.damping_ratio", dim::none, 0.05);
  if (!(b.damping_ratio >= 0 && b.damping_ratio < 1)) in.fail("bag.film.damping_ratio", "must be in [0, 1)");
  b.mass_scaling = in.quantity("bag.film.mass_scaling", dim::none, 1.0);
  if (!(b.mass_scaling >= 1)) in.fail("bag.film.mass_scaling", "must be >= 1 (film node masses x this)");
}

// Where and what the balls of a bag are (saved, or filled from its contents).
struct SavedBagPlacement {
  Vec3 centre;        // bag.centre (or the cavity's centre), in the world at rest (m)
  Vec3 rest_cavity;   // the cavity's position at rest (m)
  double r, d;        // the balls' radius and diameter (m)
  int ball_material;
};

// bag.from: the saved bag's film and balls, placed so its balls' centroid sits at bag.centre when
// given, else where it was saved.
void place_saved_bag(const CaseReader& in, Scene& s, const SavedBagPlacement& at, Bag& b) {
  if (in.has("bag.film.shrink"))
    in.fail("bag.film.shrink", "does not apply to a saved bag (bag.from): its film's unstretched shape is saved with it");
  const std::string path = in.file_path("bag.from", s.case_dir);
  SavedBag saved = load_bag(path);
  b.rest = std::move(saved.rest);
  build_topology(b.rest);
  // Placed so its balls' centroid sits at bag.centre when given, else where it was saved.
  Vec3 shift = at.rest_cavity;
  if (in.has("bag.centre")) {
    Vec3 c(0, 0, 0);
    for (const Vec3& x : saved.ball_position) c += x;
    shift = at.centre - c / static_cast<double>(saved.ball_position.size());
  }
  for (Vec3& v : b.rest.vertices) v += shift;
  b.x0 = saved.film_position;
  for (Vec3& v : b.x0) v += shift;
  b.ball_first = s.particles.size();
  b.balls = saved.ball_position.size();
  for (std::size_t k = 0; k < saved.ball_position.size(); ++k) {
    if (std::abs(saved.ball_radius[k] - at.r) > 1e-9 * at.r)
      in.fail("bag.from", "holds balls of diameter " + std::to_string(2 * saved.ball_radius[k]) +
                              " m, but bag.balls.diameter is " + std::to_string(at.d) + " m");
    s.particles.push_back({saved.ball_position[k] + shift, Vec3::Zero(), Vec3::Zero(), at.r, at.ball_material});
  }
  b.shape = saved.shape;
  b.axis = saved.axis;
  b.side = saved.side;
  b.size = saved.size;
  b.fill_fraction = saved.fill_fraction;
  b.source = "from " + in.string("bag.from");  // as the case gives it (relative to the case): a moved case reads the same
  // The count, mass or ratio and the seed of the saved case are not used (but are not unknown).
  for (const char* k : {"count", "mass", "mass_ratio", "primary_mass", "seed"}) in.has(std::string("bag.balls.") + k);
  for (const char* k : {"radius", "length", "size", "aspect", "exponent", "fill_fraction", "triangles", "shape", "axis", "side"})
    in.has(std::string("bag.") + k);
}

// The film at rest must fit the cavity: every node inside its bounds and clear of its walls.
void check_fits_cavity(const CaseReader& in, const Scene& s, const Bag& b, const Vec3& rest_cavity) {
  const double t = b.film.thickness;
  for (const Vec3& v : b.x0) {
    const Vec3 local = v - rest_cavity;
    bool inside = (local - s.cavity_lo).minCoeff() >= 0 && (s.cavity_hi - local).minCoeff() >= 0;
    for (const Wall& w : s.walls) {
      Vec3 n;
      inside = inside && wall_distance(w, local, n) >= 0.5 * t;
    }
    for (const MeshWall& w : s.mesh_walls) inside = inside && winding_number(w.mesh, w.mesh.vertices, local) > 0.5;
    if (!inside) {
      std::ostringstream m;
      m << "the bag (" << 1e3 * b.size.x() << " x " << 1e3 * b.size.y() << " x " << 1e3 * b.size.z()
        << " mm at rest) does not fit the cavity: its film reaches (" << 1e3 * local.x() << ", " << 1e3 * local.y()
        << ", " << 1e3 * local.z() << ") mm. Give a smaller bag (bag.radius, bag.length, bag.size, fewer balls), move "
        << "it (bag.centre), or enlarge the cavity";
      in.fail("bag", m.str());
    }
  }
}

// bag.film.self_radius against the film at rest: from 0.3 of the mean edge (two spheres must span a
// triangle's circumradius, 0.58 of its edge, or a layer's node passes between another's) to below
// half the distance of the nearest two nodes that are not along an edge, at rest (the film would
// start pressed against itself).
void check_self_radius(const CaseReader& in, const Bag& b) {
  const double r = b.self_radius, e = b.mean_edge;
  std::ostringstream m;
  if (r < 0.3 * e || r > 0.8 * e) {
    m << "must be from 0.3 to 0.8 of the film's mean edge " << e << " m (from " << 0.3 * e << " to " << 0.8 * e
      << " m; \"auto\" is 0.4): smaller, another layer's nodes pass between the spheres; larger, the film starts pressed "
      << "against itself";
    in.fail("bag.film.self_radius", m.str());
  }
  const std::vector<Vec3>& x = b.rest.vertices;  // the film's own shape (a saved bag's nodes may be crumpled)
  CandidatePairs near;
  make_broad_phase("hash")->find(x, std::vector<double>(x.size(), r), 0.0, near);
  std::vector<std::array<std::uint32_t, 2>> edges = b.rest.edge_vertices;  // lower index first, sorted below
  std::sort(edges.begin(), edges.end());
  double closest = HUGE_VAL;
  for (std::uint32_t i = 0; i + 1 < near.begin.size(); ++i)
    for (std::uint32_t k = near.begin[i]; k < near.begin[i + 1]; ++k) {
      const std::uint32_t j = near.partner[k];
      if (std::binary_search(edges.begin(), edges.end(), std::array<std::uint32_t, 2>{std::min(i, j), std::max(i, j)})) continue;
      closest = std::min(closest, (x[i] - x[j]).norm());
    }
  if (closest < 2 * r) {
    m << "is too large for this film: two of its nodes not along an edge are " << closest << " m apart at rest, so "
      << "their spheres (radius " << r << " m) start pressed together. Give at most " << 0.5 * closest
      << " m, or \"auto\"";
    in.fail("bag.film.self_radius", m.str());
  }
}

// The film's time and length scales: the Kelvin-Voigt damping time, the lightest node, the top
// frequency, and the film-wall contact radius.
void set_film_scales(const CaseReader& in, Bag& b) {
  // Damping time of the Kelvin-Voigt stress: ratio zeta at the film's highest frequency.
  Membrane probe(b.rest, b.film);
  b.min_node_mass = *std::min_element(probe.node_mass().begin(), probe.node_mass().end()) * b.mass_scaling;
  b.max_frequency = probe.max_frequency() / std::sqrt(b.mass_scaling);
  b.bending_frequency = probe.bending_frequency() / std::sqrt(b.mass_scaling);
  b.film.damping_time = 2 * b.damping_ratio / b.max_frequency;
  // Film-wall contact radius: half the mean edge length (the patch a node stands for).
  double edges = 0;
  for (const auto& e : b.rest.edge_vertices) edges += (b.rest.vertices[e[0]] - b.rest.vertices[e[1]]).norm();
  b.mean_edge = edges / static_cast<double>(b.rest.edge_vertices.size());
  b.contact_radius = in.quantity_or_auto("bag.film.contact_radius", dim::length).value_or(0.5 * b.mean_edge);
  if (!(b.contact_radius > 0)) in.fail("bag.film.contact_radius", "must be > 0 or \"auto\"");
  // Film-film contact: a node's sphere of 0.4 mean edges keeps another layer's nodes from passing
  // between its nodes (a triangle's circumradius is 0.58 of its edge, below two such radii).
  const bool self = in.boolean("bag.film.self_contact", true);
  const double self_radius = in.quantity_or_auto("bag.film.self_radius", dim::length).value_or(0.4 * b.mean_edge);
  if (!(self_radius > 0)) in.fail("bag.film.self_radius", "must be > 0 or \"auto\"");
  b.self_radius = self ? self_radius : 0.0;
  if (self) check_self_radius(in, b);
}

}  // namespace

// The bag's film at a given volume, as bag.shape asks: a capsule keeps its radius and gets
// longer, a pillow keeps its proportions. Explicit dimensions are used as given; `sized`: whether
// the size follows the volume (none was given).
std::function<void(double)> shape_at_volume(const CaseReader& in, const Scene& s, Bag& b, const SavedBagPlacement& at,
                                            std::size_t n, long long triangles, bool& sized) {
  const double r = at.r, d = at.d, t = b.film.thickness;
  const Vec3 centre = at.centre;
  const Vec3 height_dir = b.axis.cross(b.side);
  std::function<void(double)> make;
  if (b.shape == "capsule") {
    // Radius: given, or 40% of the cavity's smallest extent across the axis.
    const Vec3 ext = s.cavity_hi - s.cavity_lo;
    const double across = std::min(ext.dot(b.side.cwiseAbs()), ext.dot(height_dir.cwiseAbs()));
    const double radius = in.quantity("bag.radius", dim::length, 0.4 * across);
    // A lattice needs a radius above one ball diameter; a single ball sits on the axis.
    const double least = n == 1 ? 1.02 * r + 0.5 * t : 2 * r;
    if (!(radius > least))
      in.fail("bag.radius", n == 1 ? "must exceed the ball's radius plus half the film's thickness (one ball)"
                                   : "must be larger than a ball's diameter");
    double fixed_length = 0;
    if (in.has("bag.length")) {
      fixed_length = in.quantity("bag.length", dim::length);
      if (!(fixed_length >= 2 * radius)) in.fail("bag.length", "must be at least 2 x bag.radius (tip to tip)");
    }
    sized = fixed_length == 0;
    make = [&b, centre, triangles, radius, fixed_length](double volume) {
      const double length = fixed_length > 0 ? fixed_length
                                             : std::max(2 * radius, (volume - 4.0 / 3.0 * kPi * radius * radius * radius) /
                                                                            (kPi * radius * radius) + 2 * radius);
      b.rest = capsule_mesh(centre, b.axis, radius, length, static_cast<std::size_t>(triangles));
      b.size = Vec3(length, 2 * radius, 2 * radius);
    };
  } else {
    const double exponent = in.quantity("bag.exponent", dim::none, 4.0);
    if (!(exponent >= 2 && exponent <= 20)) in.fail("bag.exponent", "must be in [2, 20] (2 = ellipsoid, larger = boxier)");
    Vec3 fixed_size = Vec3::Zero(), aspect(2.0, 1.0, 0.6);
    if (in.has("bag.size")) {
      fixed_size = in.vector("bag.size", dim::length);
      if (!(fixed_size.minCoeff() > 2 * d)) in.fail("bag.size", "every extent must exceed two ball diameters");
    } else {
      aspect = in.vector("bag.aspect", dim::none, aspect);
      if (!(aspect.minCoeff() > 0)) in.fail("bag.aspect", "must be three positive numbers (length, width, height)");
    }
    sized = fixed_size.norm() == 0;
    make = [&b, centre, triangles, sized, exponent, fixed_size, aspect](double volume) {
      const Vec3 size = sized ? Vec3(std::cbrt(volume / superellipsoid_volume(0.5 * aspect, exponent)) * aspect) : fixed_size;
      b.rest = pillow_mesh(centre, b.axis, b.side, size, exponent, static_cast<std::size_t>(triangles));
      b.size = size;
    };
  }
  return make;
}

// The balls of a bag sized from its contents: the count of bag.balls, the film at fill_fraction
// (shape_at_volume), the lattice filled lowest sites first.
void fill_from_contents(const CaseReader& in, Scene& s, const SavedBagPlacement& at, std::uint64_t seed, long long triangles,
                        double ball_mass, Bag& b) {
  const double r = at.r, t = b.film.thickness;
  const Vec3 centre = at.centre;
  const int ball_material = at.ball_material;
  const std::size_t n = ball_count(in, ball_mass, s.primary ? s.primary->structure_mass : 0.0);
  const double ball_volume = static_cast<double>(n) * 4.0 / 3.0 * kPi * r * r * r;
  b.fill_fraction = in.quantity("bag.fill_fraction", dim::none, 0.5);
  if (!(b.fill_fraction > 0 && b.fill_fraction < 0.7))
    in.fail("bag.fill_fraction", "must be in (0, 0.7): ball volume / bag volume when the bag is sized from its contents");
  bool sized = false;
  const std::function<void(double)> make = shape_at_volume(in, s, b, at, n, triangles, sized);
  // Sized from the contents: the volume at fill_fraction, grown by 5% steps until the lattice
  // holds every ball (a small bag loses much of its volume to the layer along the film).
  double volume = ball_volume / b.fill_fraction;
  std::vector<Vec3> sites;
  for (int attempt = 0;; ++attempt) {
    make(volume);
    sites = n == 1 ? single_site(b.rest, centre, r, 0.5 * t, seed) : lattice_sites(b.rest, centre, r, 0.5 * t, s.gravity, seed);
    if (sites.size() >= n || !sized || attempt == 40) break;
    volume *= 1.05;
  }
  b.x0 = b.rest.vertices;
  pull_tight(in, ball_volume, b);
  b.fill_fraction = ball_volume / enclosed_volume(b.rest, b.rest.vertices);
  if (sites.size() < n) {
    std::ostringstream m;
    m << "asks for " << n << " balls, but the bag holds at most " << sites.size()
      << " on a lattice (bag volume " << enclosed_volume(b.rest, b.rest.vertices) * 1e6
      << " cm^3); give a larger bag (bag.radius, bag.length or bag.size), or leave its length or size out so "
         "that it is sized from its contents";
    in.fail(in.has("bag.balls.count") ? "bag.balls.count" : in.has("bag.balls.mass") ? "bag.balls.mass" : "bag.balls.mass_ratio", m.str());
  }
  b.ball_first = s.particles.size();
  b.balls = n;
  for (std::size_t k = 0; k < n; ++k) s.particles.push_back({sites[k], Vec3::Zero(), Vec3::Zero(), r, ball_material});
  std::ostringstream src;
  if (n == 1)
    src << "one ball near the bag's centre, within half its radius (seed " << seed << ")";
  else
    src << "filled on an FCC lattice, lowest sites first (seed " << seed << ")";
  b.source = src.str();
}

void resolve_bag(const CaseReader& in, Scene& s, const std::vector<std::string>& names) {
  if (!in.has("bag")) return;
  auto bag = std::make_shared<Bag>();
  Bag& b = *bag;

  read_film(in, s, names, b);

  // The balls.
  const int ball_material = material_index(in, "bag.balls.material", names);
  const double d = in.quantity("bag.balls.diameter", dim::length);
  if (!(d > 0)) in.fail("bag.balls.diameter", "must be > 0 (m)");
  const double r = 0.5 * d;
  const double ball_mass = sphere_mass(s.materials[static_cast<std::size_t>(ball_material)].density, r);
  const std::uint64_t seed = static_cast<std::uint64_t>(in.integer("bag.balls.seed", static_cast<long long>(s.seed), 0, kMaxSeed));

  b.shape = in.choice("bag.shape", {"capsule", "pillow"}, "capsule");
  b.axis = unit_vector(in, "bag.axis", Vec3::UnitX());
  const Vec3 up_hint = s.gravity.norm() > 0 ? Vec3(-s.gravity.normalized()) : Vec3::UnitZ();
  Vec3 side_default = up_hint.cross(b.axis);
  if (side_default.norm() < 1e-6) side_default = b.axis.unitOrthogonal();
  b.side = unit_vector(in, "bag.side", side_default.normalized());
  b.side = (b.side - b.side.dot(b.axis) * b.axis);
  if (b.side.norm() < 1e-6) in.fail("bag.side", "must not be parallel to bag.axis");
  b.side.normalize();
  const Vec3 rest_cavity = s.motion->at(0.0).position;
  const Vec3 centre = in.vector("bag.centre", dim::length, 0.5 * (s.cavity_lo + s.cavity_hi)) + rest_cavity;
  const long long triangles = in.integer("bag.triangles", 800);
  if (triangles < 20 || triangles > 2000000) in.fail("bag.triangles", "must be in [20, 2e6] (the film's resolution)");

  if (in.has("bag.from")) {
    place_saved_bag(in, s, {centre, rest_cavity, r, d, ball_material}, b);
  } else {
    fill_from_contents(in, s, {centre, rest_cavity, r, d, ball_material}, seed, triangles, ball_mass, b);
  }
  for (std::size_t k = b.ball_first; k < s.particles.size(); ++k)
    for (std::size_t j = 0; j < b.ball_first; ++j)
      if ((s.particles[k].x - s.particles[j].x).norm() < s.particles[k].radius + s.particles[j].radius)
        in.fail("bag", "a ball of the bag overlaps particle " + std::to_string(j) + " of [particles]; move the bag (bag.centre) or the particles");

  check_fits_cavity(in, s, b, rest_cavity);

  set_film_scales(in, b);
  resolve_strings(in, b, s);
  s.bag = std::move(bag);
}

// bag.film.bending_interval: N in [1, 64] (default 1: every step) or "auto". Auto: the largest N up to 4 whose
// slow step N dt stays within 0.5 / omega of the stiffest hinge before its fade (a wing at a tenth
// of its area turns 10x faster than at rest: 10 x Bag::bending_frequency), a quarter of the
// impulse scheme's stability limit omega N dt < 2; 1 when bending is that fast or absent. The cap
// keeps the clock's own error (second order in N dt) small beside the chaos of a bag. Not the default:
// the impulses feed the film's fast modes, whose damping then dissipates energy no force supplied
// (about 2e-6 W on the flagship's bag), which spoils the energy balance of a weakly driven bag
// (docs/bag.md, "Time step").
void resolve_bending_clock(const CaseReader& in, Scene& s) {
  const char* key = "bag.film.bending_interval";
  if (!s.bag) return;
  auto b = std::make_shared<Bag>(*s.bag);
  if (!in.has(key) || !in.is_string(key)) {
    b->bending_interval = static_cast<int>(in.integer(key, 1, 1, 64));
  } else {
    if (in.string(key) != "auto") in.fail(key, "must be \"auto\" or a whole number of steps from 1 to 64");
    const double slow = 0.5 / (10.0 * b->bending_frequency * s.dt);  // the largest N allowed
    b->bending_interval = b->bending_frequency > 0 ? static_cast<int>(std::clamp(std::floor(slow), 1.0, 4.0)) : 1;
  }
  s.bag = std::move(b);
}

}  // namespace bagdem
