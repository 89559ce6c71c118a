// Particles of a case, group by group ([particles.<group>]), in one of three ways:
//   explicit  positions = [[x, y, z], ...] with diameter (or diameters = [...]), optional velocities
//   file      file = "name.csv" (header; columns x, y, z, diameter [, vx, vy, vz [, wx, wy, wz]],
//             SI) or format = "lammps-data" (atom_style granular: id type diameter density x y z;
//             optional Velocities section: id vx vy vz wx wy wz; the file's density is ignored,
//             the group's material sets it); either may be gzip-compressed (name.gz)
//   generated count or total_mass, diameter or [diameter_distribution], fill = "random" (random
//             sequential addition) or "lattice" (FCC sites, lowest first along gravity), region,
//             seed; never overlapping each other, earlier groups, or the walls.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "bagdem/case/load_case.hpp"
#include "bagdem/contact/sphere_triangle.hpp"
#include "bagdem/error.hpp"
#include "bagdem/io/text_file.hpp"
#include "bagdem/particles.hpp"
#include "fcc_lattice.hpp"

namespace bagdem {
namespace {

// Is a sphere (x, r) inside the cavity, not touching any wall (tolerance: allowed overlap)?
bool inside_cavity(const Scene& s, const Vec3& x, double r, double tolerance = 0.0) {
  r -= tolerance;
  for (const Wall& w : s.walls) {
    Vec3 n;
    if (wall_distance(w, x, n) < r) return false;
  }
  for (int k = 0; k < 3; ++k)
    if (x[k] - r < s.cavity_lo[k] || x[k] + r > s.cavity_hi[k]) return false;
  for (const MeshWall& w : s.mesh_walls) {
    if (winding_number(w.mesh, w.mesh.vertices, x) < 0.5) return false;
    for (const auto& t : w.mesh.triangles) {
      const TriangleHit h = closest_point_on_triangle(x, w.mesh.vertices[t[0]], w.mesh.vertices[t[1]], w.mesh.vertices[t[2]]);
      if (h.distance2 < r * r) return false;
    }
  }
  return true;
}

// Uniform grid over occupied space for overlap queries while placing particles.
class PlacementGrid {
 public:
  explicit PlacementGrid(double cell) : h_(cell) {}
  void add(const Vec3& x, double r, std::size_t id) {
    cells_[key(x)].push_back(id);
    pos_.resize(std::max(pos_.size(), id + 1));
    rad_.resize(pos_.size());
    pos_[id] = x;
    rad_[id] = r;
  }
  // Index of a particle overlapping (x, r) by more than `tolerance` times the smaller radius, or -1.
  long overlapping(const Vec3& x, double r, double tolerance = 0.0) const {
    const auto c = cell(x);
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto it = cells_.find(pack(c[0] + dx, c[1] + dy, c[2] + dz));
          if (it == cells_.end()) continue;
          for (std::size_t id : it->second) {
            const double cut = r + rad_[id] - tolerance * std::min(r, rad_[id]);
            if ((pos_[id] - x).squaredNorm() < cut * cut) return static_cast<long>(id);
          }
        }
    return -1;
  }

 private:
  std::array<long long, 3> cell(const Vec3& x) const {
    return {static_cast<long long>(std::floor(x.x() / h_)), static_cast<long long>(std::floor(x.y() / h_)),
            static_cast<long long>(std::floor(x.z() / h_))};
  }
  static long long pack(long long a, long long b, long long c) {
    return (a & 0x1FFFFF) | ((b & 0x1FFFFF) << 21) | ((c & 0x1FFFFF) << 42);
  }
  long long key(const Vec3& x) const {
    const auto c = cell(x);
    return pack(c[0], c[1], c[2]);
  }
  double h_;
  std::unordered_map<long long, std::vector<std::size_t>> cells_;
  std::vector<Vec3> pos_;
  std::vector<double> rad_;
};

struct Group {
  std::string key;   // "particles.<name>"
  int material = 0;
  double density = 0;
};

// A particle file's text (gzip-compressed or not), or an input error naming the key.
std::istringstream particle_file(const CaseReader& in, const std::string& key, const std::string& path) {
  std::optional<std::string> text;
  try {
    text = read_text_file(path);
  } catch (const std::runtime_error& e) {
    in.fail(key, e.what());
  }
  if (!text) in.fail(key, "cannot open the file " + path);
  return std::istringstream(std::move(*text));
}

std::vector<ParticleInit> read_csv(const CaseReader& in, const std::string& key, const std::string& path) {
  std::istringstream f = particle_file(in, key, path);
  std::vector<ParticleInit> out;
  std::string line;
  std::getline(f, line);  // header
  int row = 1;
  while (std::getline(f, line)) {
    ++row;
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream s(line);
    std::vector<double> v;
    double d;
    while (s >> d) v.push_back(d);
    if (v.size() != 4 && v.size() != 7 && v.size() != 10)
      in.fail(key, path + " row " + std::to_string(row) +
                       ": expected 4, 7 or 10 numbers (x y z diameter [vx vy vz [wx wy wz]])");
    ParticleInit p;
    p.x = {v[0], v[1], v[2]};
    p.radius = 0.5 * v[3];
    if (v.size() >= 7) p.v = {v[4], v[5], v[6]};
    if (v.size() == 10) p.w = {v[7], v[8], v[9]};
    out.push_back(p);
  }
  if (out.empty()) in.fail(key, path + " holds no particles (a header line, then a row per particle)");
  return out;
}

std::vector<ParticleInit> read_lammps_data(const CaseReader& in, const std::string& key,
                                           const std::string& path) {
  std::istringstream f = particle_file(in, key, path);
  std::vector<ParticleInit> out;
  std::unordered_map<long, std::size_t> by_id;
  std::string line, section;
  long declared = -1;  // the header's "N atoms"
  while (std::getline(f, line)) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos) continue;
    if (section != "Atoms" && section != "Velocities") {  // the header: "N atoms" is the count the Atoms section must hold
      std::istringstream h(line);
      long count = 0;
      std::string word;
      if (h >> count >> word && word == "atoms") declared = count;
    }
    if (std::isalpha(static_cast<unsigned char>(line[first]))) {
      section = line.substr(first, line.find_first_of(" \t\r#", first) - first);
      continue;
    }
    std::istringstream s(line);
    if (section == "Atoms") {
      long id, type;
      double dia, rho;
      ParticleInit p;
      if (!(s >> id >> type >> dia >> rho >> p.x.x() >> p.x.y() >> p.x.z()))
        in.fail(key, path + ": Atoms line is not 'id type diameter density x y z': " + line);
      p.radius = 0.5 * dia;
      by_id[id] = out.size();
      out.push_back(p);
    } else if (section == "Velocities") {
      long id;
      Vec3 v, w;
      if (!(s >> id >> v.x() >> v.y() >> v.z() >> w.x() >> w.y() >> w.z()))
        in.fail(key, path + ": Velocities line is not 'id vx vy vz wx wy wz': " + line);
      auto it = by_id.find(id);
      if (it == by_id.end()) in.fail(key, path + ": velocity for unknown atom id " + std::to_string(id));
      out[it->second].v = v;
      out[it->second].w = w;
    }
  }
  if (out.empty()) in.fail(key, path + " has no Atoms section");
  if (declared >= 0 && static_cast<long>(out.size()) != declared)
    in.fail(key, path + " declares " + std::to_string(declared) + " atoms in its header but its Atoms section holds " +
                     std::to_string(out.size()) + " (a truncated or edited file)");
  return out;
}

// Diameter sampler for a generated group.
struct DiameterSampler {
  std::string kind = "fixed";
  double d = 0, lo = 0, hi = 0, mean = 0, std = 0;
  double mean_volume = 0;  // for count from total mass
  double draw(std::mt19937_64& rng) const {
    if (kind == "fixed") return d;
    if (kind == "uniform") return std::uniform_real_distribution<double>(lo, hi)(rng);
    std::normal_distribution<double> g(mean, std);
    for (;;) {
      const double x = g(rng);
      if (x >= lo && x <= hi) return x;
    }
  }
  double max() const { return kind == "fixed" ? d : hi; }
};

DiameterSampler diameter_sampler(const CaseReader& in, const std::string& g) {
  DiameterSampler s;
  if (in.has(g + ".diameter")) {
    s.d = in.quantity(g + ".diameter", dim::length);
    if (!(s.d > 0)) in.fail(g + ".diameter", "must be > 0");
    return s;
  }
  const std::string dd = g + ".diameter_distribution";
  if (!in.has(dd)) in.fail(g + ".diameter", "is required (or a [" + dd + "] table)");
  s.kind = in.choice(dd + ".kind", {"uniform", "normal"}, "uniform");
  s.lo = in.quantity(dd + ".min", dim::length);
  s.hi = in.quantity(dd + ".max", dim::length);
  if (!(s.lo > 0)) in.fail(dd + ".min", "must be > 0");
  if (!(s.hi > s.lo)) in.fail(dd + ".max", "must exceed " + dd + ".min");
  if (s.kind == "normal") {
    s.mean = in.quantity(dd + ".mean", dim::length);
    s.std = in.quantity(dd + ".std", dim::length);
    if (!(s.std > 0)) in.fail(dd + ".std", "must be > 0");
    if (!(s.mean >= s.lo && s.mean <= s.hi)) in.fail(dd + ".mean", "must lie within [min, max]");
  }
  return s;
}

// Explicit particles may touch (a settled bed has contact overlaps of ~1e-5 of a radius): an
// overlap above `tol` times the smaller radius, with a wall or another particle, is an input error.
void check_explicit(const CaseReader& in, const std::string& key, const Scene& s,
                    const std::vector<ParticleInit>& list, std::size_t first, PlacementGrid& grid, double tol) {
  for (std::size_t k = 0; k < list.size(); ++k) {
    const ParticleInit& p = list[k];
    if (!(p.radius > 0)) in.fail(key, "particle " + std::to_string(k) + " has a non-positive diameter");
    if (!inside_cavity(s, p.x, p.radius, tol * p.radius)) {
      std::ostringstream m;
      m << "particle " << k << " at (" << p.x.x() << ", " << p.x.y() << ", " << p.x.z()
        << ") m with diameter " << 2 * p.radius << " m is not inside the cavity (it crosses a wall by more "
        << "than simulation.initial_overlap = " << tol << " of its radius)";
      in.fail(key, m.str());
    }
    if (long other = grid.overlapping(p.x, p.radius, tol); other >= 0)
      in.fail(key, "particles " + std::to_string(other) + " and " + std::to_string(first + k) +
                       " overlap by more than simulation.initial_overlap = " + std::to_string(tol) +
                       " of the smaller radius; explicit particles must not overlap");
    grid.add(p.x, p.radius, first + k);
  }
}

void generate(const CaseReader& in, const std::string& g, const Group& grp, Scene& s,
              PlacementGrid& grid, std::uint64_t seed) {
  const DiameterSampler ds = diameter_sampler(in, g);
  std::mt19937_64 rng(seed);
  // The diameters first (count, or total mass reached), then the places.
  std::vector<double> diameters;
  if (in.has(g + ".count") == in.has(g + ".total_mass"))
    in.fail(g + ".count", "give exactly one of count and total_mass");
  if (in.has(g + ".count")) {
    const long long n = in.integer(g + ".count", 0);
    if (n < 1 || n > 50'000'000) in.fail(g + ".count", "must be between 1 and 5e7");
    for (long long k = 0; k < n; ++k) diameters.push_back(ds.draw(rng));
  } else {
    const double M = in.quantity(g + ".total_mass", dim::mass);
    if (!(M > 0)) in.fail(g + ".total_mass", "must be > 0");
    double m = 0;
    const double rho = grp.density;
    // Add balls while that brings the total closer to M (so a 8% bag of 4-mm balls is the nearest count).
    for (;;) {
      const double d = ds.draw(rng);
      const double mb = sphere_mass(rho, 0.5 * d);
      if (m + mb - M > M - m && !diameters.empty()) break;
      diameters.push_back(d);
      m += mb;
      if (diameters.size() > 50'000'000) in.fail(g + ".total_mass", "needs more than 5e7 particles");
    }
  }
  // Largest first: random sequential addition jams much later that way (the sizes drawn are the same).
  std::sort(diameters.begin(), diameters.end(), std::greater<>());
  const Vec3 lo = in.vector(g + ".region_min", dim::length, s.cavity_lo);
  const Vec3 hi = in.vector(g + ".region_max", dim::length, s.cavity_hi);
  const Vec3 v0 = in.vector(g + ".velocity", dim::speed, Vec3::Zero());
  const std::string fill = in.choice(g + ".fill", {"random", "lattice"}, "random");
  const double dmax = ds.max();
  std::optional<FccLattice> lattice;
  if (fill == "lattice") {
    // FCC sites, nearest-neighbour distance 1.01 dmax, lowest first along gravity (or z).
    const Vec3 down = s.gravity.norm() > 0 ? Vec3(s.gravity.normalized()) : Vec3(-Vec3::UnitZ());
    try {
      lattice.emplace(lo, hi, 1.01 * dmax, down, diameters.size());
    } catch (const std::length_error& e) {
      std::ostringstream m;
      const Vec3 size = hi - lo;
      m << "the lattice over the region (" << size.x() << " x " << size.y() << " x " << size.z() << " m) has " << e.what()
        << " (at most " << FccLattice::kMaxLayerSites << ") for " << diameters.size() << " particles of " << dmax
        << " m: check the units of the cavity's keys and of " << g << ".region_min/region_max (a plain number is in metres, write "
        << "\"20 mm\" for millimetres), or use fill = \"random\"";
      in.fail(g + ".fill", m.str());
    }
  }
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const std::size_t max_attempts = 1000 * diameters.size() + 100000;
  std::size_t attempts = 0;
  for (double d : diameters) {
    const double r = 0.5 * d;
    for (;;) {
      Vec3 x;
      if (lattice) {
        if (!lattice->next(x))
          in.fail(g + ".count", "only " + std::to_string(s.particles.size()) +
                                    " particles fit on the lattice in the region; enlarge the region or lower the count");
        // Small jitter (1% of d) breaks the lattice symmetry reproducibly.
        x += 0.005 * d * draw_vec3([&] { return 2 * U(rng) - 1; });
      } else {
        if (++attempts > max_attempts)
          in.fail(g + ".count", "could not place the particles without overlap after " +
                                    std::to_string(max_attempts) + " random tries (" +
                                    std::to_string(s.particles.size()) +
                                    " placed); enlarge the region, lower the count, or use fill = \"lattice\"");
        for (int k = 0; k < 3; ++k) x[k] = lo[k] + r + (hi[k] - lo[k] - 2 * r) * U(rng);
      }
      if (!inside_cavity(s, x, r * 1.0000001) || grid.overlapping(x, r) >= 0) continue;
      grid.add(x, r, s.particles.size());
      ParticleInit p;
      p.x = x;
      p.v = v0;
      p.radius = r;
      p.material = grp.material;
      s.particles.push_back(p);
      break;
    }
  }
}

}  // namespace

void resolve_particles(const CaseReader& in, Scene& s, const std::vector<std::string>& materials) {
  const auto groups = in.keys("particles");
  if (groups.empty()) return;  // a bag may hold all the balls (checked in load_case)
  double dmax = 0;
  // The placement grid cell must cover the largest diameter of any group: a first pass over sizes.
  for (const auto& name : groups) {
    const std::string g = "particles." + name;
    if (in.has(g + ".diameter")) dmax = std::max(dmax, in.quantity(g + ".diameter", dim::length));
    if (in.has(g + ".diameter_distribution.max"))
      dmax = std::max(dmax, in.quantity(g + ".diameter_distribution.max", dim::length));
  }
  PlacementGrid grid(dmax > 0 ? dmax : 1e-3);
  const double extent = (s.cavity_hi - s.cavity_lo).minCoeff();
  for (std::size_t gi = 0; gi < groups.size(); ++gi) {
    const std::string g = "particles." + groups[gi];
    Group grp{g, 0, 0};
    const std::string mat = in.string(g + ".material");
    const auto it = std::find(materials.begin(), materials.end(), mat);
    if (it == materials.end()) in.fail(g + ".material", "must name a material defined under [materials]");
    grp.material = static_cast<int>(it - materials.begin());
    grp.density = s.materials[static_cast<std::size_t>(grp.material)].density;

    std::vector<ParticleInit> list;
    std::string key;
    if (in.has(g + ".positions")) {
      key = g + ".positions";
      const auto xs = in.vector_list(key, dim::length);
      std::vector<double> dia;
      if (in.has(g + ".diameters")) {
        for (std::size_t k = 0; k < in.array_size(g + ".diameters"); ++k)
          dia.push_back(in.quantity(g + ".diameters." + std::to_string(k), dim::length));
        if (dia.size() != xs.size()) in.fail(g + ".diameters", "needs one diameter per position");
      } else {
        dia.assign(xs.size(), in.quantity(g + ".diameter", dim::length));
      }
      std::vector<Vec3> vs = in.has(g + ".velocities") ? in.vector_list(g + ".velocities", dim::speed)
                                                       : std::vector<Vec3>(xs.size(), Vec3::Zero());
      if (vs.size() != xs.size()) in.fail(g + ".velocities", "needs one velocity per position");
      for (std::size_t k = 0; k < xs.size(); ++k) list.push_back({xs[k], vs[k], Vec3::Zero(), 0.5 * dia[k], 0});
    } else if (in.has(g + ".file")) {
      key = g + ".file";
      const std::string path = in.file_path(key, s.case_dir);
      const std::string format = in.choice(g + ".format", {"csv", "lammps-data"}, "csv");
      list = format == "csv" ? read_csv(in, key, path) : read_lammps_data(in, key, path);
    }
    if (!key.empty()) {
      const double tol = in.quantity("simulation.initial_overlap", dim::none, 1e-3);
      if (!(tol >= 0 && tol < 0.1)) in.fail("simulation.initial_overlap", "must be in [0, 0.1)");
      // A ball may fit snugly (zero clearance: it touches both walls), within the overlap tolerance.
      for (auto& p : list) {
        p.material = grp.material;
        if (2 * p.radius > extent + 2 * tol * p.radius)
          in.fail(key, "a particle of diameter " + std::to_string(2 * p.radius) +
                           " m is larger than the cavity (smallest extent " + std::to_string(extent) + " m)");
      }
      check_explicit(in, key, s, list, s.particles.size(), grid, tol);
      s.particles.insert(s.particles.end(), list.begin(), list.end());
      continue;
    }
    const DiameterSampler ds = diameter_sampler(in, g);
    if (ds.max() >= extent)
      in.fail(in.has(g + ".diameter") ? g + ".diameter" : g + ".diameter_distribution.max",
              "particles larger than the cavity (smallest extent " + std::to_string(extent) + " m)");
    const auto seed = static_cast<std::uint64_t>(in.integer(g + ".seed", static_cast<long long>(s.seed + gi), 0, kMaxSeed));
    generate(in, g, grp, s, grid, seed);
  }
}

}  // namespace bagdem
