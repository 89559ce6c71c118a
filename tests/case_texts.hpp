// Test support: case.toml texts built from named pieces, and the case texts several suites share.
//
// CaseText is an ordered set of TOML tables: a scene is written as a chain of pieces
// (simulation, materials, interactions, cavity, motion, particles, bag, primary, output), and a
// test's variant as "this scene, but with X changed" (set, erase, or one more piece). The pieces
// take TOML values (see Value): "4 mm" is written quoted (a quantity with its unit), 0.3 or "0.3"
// bare, "[1, 0, 0]" as it is. Tables keep the order in which they were first set (the order of
// [materials] and [particles] tables is the engine's material and particle order), keys theirs.
// (scene_builder.hpp builds a Scene in code instead, without a case file.)
#pragma once
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

namespace bagdem::testing {

// `v` with `digits` significant digits (%.*g); by default the fewest that give the double back,
// and a whole number as %.17g writes it ("20", a TOML integer; not "2e+01", which TOML reads as a
// float).
inline std::string num(double v, int digits = 0) {
  char b[64];
  if (digits == 0) {
    std::snprintf(b, sizeof b, "%.17g", v);
    if (!std::strpbrk(b, ".eEin")) return b;
  }
  for (int d = digits > 0 ? digits : 1; d <= 17; ++d) {
    std::snprintf(b, sizeof b, "%.*g", d, v);
    if (digits > 0 || std::strtod(b, nullptr) == v) break;
  }
  return b;
}

// A TOML string: quoted("capsule") is "\"capsule\"".
inline std::string quoted(const std::string& s) { return "\"" + s + "\""; }

// A TOML value as written in case.toml: text holding a space ("4 mm", "-9.81 m/s^2") is a quantity
// and written quoted, unless it is an array or a string already ("[1, 0, 0]", "\"steady\"");
// other text ("0.3", "200e9", "true") is written as it is; numbers with num().
struct Value {
  std::string toml;
  Value(const char* s) : Value(std::string(s)) {}
  Value(const std::string& s)
      : toml(!s.empty() && s[0] != '[' && s[0] != '"' && s.find(' ') != std::string::npos ? quoted(s) : s) {}
  Value(double v) : toml(num(v)) {}
  Value(int v) : toml(std::to_string(v)) {}
};

// A TOML array of three values: vec("-20 mm", 0, "12 mm") is ["-20 mm", 0, "12 mm"].
inline std::string vec(const Value& x, const Value& y, const Value& z) {
  return "[" + x.toml + ", " + y.toml + ", " + z.toml + "]";
}

// Gravity along -z, and none.
inline const char* const kGravityDown = "[0, 0, \"-9.81 m/s^2\"]";
inline const char* const kNoGravity = "[0, 0, 0]";

class CaseText {
 public:
  using Keys = std::vector<std::pair<std::string, Value>>;

  // ---- the general operations ----
  // `key = value` in [table]: replaced where it is when the key is there, else added to the table
  // (the table is added at the end when new).
  CaseText& set(const std::string& table, const std::string& key, const Value& value) {
    return set_toml(table, key, value.toml);
  }
  CaseText& set(const std::string& table, const Keys& keys) {
    table_named(table);  // the table exists even when `keys` is empty
    for (const auto& [k, v] : keys) set(table, k, v);
    return *this;
  }
  // One more [[table]] entry (an array of tables: cavity.planes, bag.strings).
  CaseText& add(const std::string& table, const Keys& keys) {
    Table t{table, true, {}};
    for (const auto& [k, v] : keys) t.keys.emplace_back(k, v.toml);
    tables_.push_back(std::move(t));
    return *this;
  }
  // Without `key` in [table]; without the whole table (or every [[table]] entry).
  CaseText& erase(const std::string& table, const std::string& key) {
    for (Table& t : tables_)
      if (t.name == table && !t.array)
        for (auto it = t.keys.begin(); it != t.keys.end(); ++it)
          if (it->first == key) {
            t.keys.erase(it);
            return *this;
          }
    return *this;
  }
  CaseText& erase(const std::string& table) {
    std::erase_if(tables_, [&](const Table& t) { return t.name == table; });
    return *this;
  }
  // `other`'s keys set here, its [[table]] entries added.
  CaseText& merge(const CaseText& other) {
    for (const Table& t : other.tables_) {
      if (t.array) {
        tables_.push_back(t);
        continue;
      }
      table_named(t.name);
      for (const auto& [k, v] : t.keys) set_toml(t.name, k, v);
    }
    return *this;
  }

  // ---- the pieces ----
  CaseText& simulation(const Value& duration, const Value& gravity = kGravityDown) {
    return set("simulation", {{"duration", duration}, {"gravity", gravity}});
  }
  CaseText& material(const std::string& name, const Value& density, const Value& youngs_modulus,
                     const Value& poisson_ratio) {
    return set("materials." + name,
               {{"density", density}, {"youngs_modulus", youngs_modulus}, {"poisson_ratio", poisson_ratio}});
  }
  // Bearing steel (7800 kg/m^3, nu 0.3), 200 GPa unless softened.
  CaseText& steel(const Value& youngs_modulus = "200 GPa") {
    return material("steel", "7800 kg/m^3", youngs_modulus, "0.3");
  }
  // The bag film: LDPE (920 kg/m^3, 0.25 GPa, nu 0.4).
  CaseText& ldpe() { return material("ldpe", "920 kg/m^3", "0.25 GPa", "0.4"); }
  // The bag suites' materials: steel softened to 2 GPa (balls, walls) and the LDPE film.
  CaseText& steel_and_film() { return steel("2 GPa").ldpe(); }
  // The soft rubber of the shaken boxes (1200 kg/m^3, 5 MPa, nu 0.45).
  CaseText& rubber() { return material("rubber", "1200 kg/m^3", "5 MPa", "0.45"); }
  // [interactions.default] (friction left out when empty); interactions("steel-ldpe", ...) for a pair.
  CaseText& interactions(const Value& restitution, const Value& friction = "") {
    return interactions("default", restitution, friction);
  }
  CaseText& interactions(const std::string& pair, const Value& restitution, const Value& friction) {
    set("interactions." + pair, "restitution", restitution);
    if (!friction.toml.empty()) set("interactions." + pair, "friction", friction);
    return *this;
  }
  // [cavity] of a kind with bounds min, max (arrays); box() is kind "box".
  CaseText& cavity(const std::string& kind, const std::string& material, const Value& min, const Value& max) {
    return set("cavity", {{"kind", quoted(kind)}, {"material", quoted(material)}, {"min", min}, {"max", max}});
  }
  CaseText& box(const std::string& material, const Value& min, const Value& max) {
    return cavity("box", material, min, max);
  }
  // One more wall of a "planes" cavity.
  CaseText& plane(const Value& point, const Value& normal) {
    return add("cavity.planes", {{"point", point}, {"normal", normal}});
  }
  // [cavity] of kind "stl" read from `file`, with `scale` (none when empty).
  CaseText& stl(const std::string& material, const std::string& file, const Value& scale = "") {
    set("cavity", {{"kind", quoted("stl")}, {"material", quoted(material)}, {"file", quoted(file)}});
    if (!scale.toml.empty()) set("cavity", "scale", scale);
    return *this;
  }
  // [cavity.motion] harmonic.
  CaseText& harmonic(const Value& amplitude, const Value& frequency, const Value& direction) {
    return set("cavity.motion", {{"kind", quoted("harmonic")}, {"amplitude", amplitude}, {"frequency", frequency},
                                 {"direction", direction}});
  }
  // [particles.<group>]: `count` balls (the fill's default placement); placed(): at `positions`,
  // with `velocities` (none when empty).
  CaseText& balls(const std::string& group, const std::string& material, const Value& diameter, const Value& count) {
    return set("particles." + group, {{"material", quoted(material)}, {"diameter", diameter}, {"count", count}});
  }
  CaseText& placed(const std::string& group, const std::string& material, const Value& diameter,
                   const Value& positions, const Value& velocities = "") {
    set("particles." + group, {{"material", quoted(material)}, {"diameter", diameter}, {"positions", positions}});
    if (!velocities.toml.empty()) set("particles." + group, "velocities", velocities);
    return *this;
  }
  // A capsule bag along x of `radius` with `triangles`: [bag], [bag.balls] (4 mm steel, `count`),
  // [bag.film] (50 um LDPE).
  CaseText& capsule_bag(const Value& radius, const Value& triangles, const Value& count) {
    set("bag", {{"shape", quoted("capsule")}, {"axis", "[1, 0, 0]"}, {"radius", radius}, {"triangles", triangles}});
    set("bag.balls", {{"material", quoted("steel")}, {"diameter", "4 mm"}, {"count", count}});
    return set("bag.film", {{"material", quoted("ldpe")}, {"thickness", "50 um"}});
  }
  // One more [[bag.strings]] entry.
  CaseText& bag_string(const std::string& at, const Value& anchor, const Value& stiffness, const Value& damping) {
    return add("bag.strings", {{"at", quoted(at)}, {"anchor", anchor}, {"stiffness", stiffness}, {"damping", damping}});
  }
  // [primary] of kind "sdof".
  CaseText& sdof(const Value& mass, const Value& stiffness, const Value& damping_ratio) {
    return set("primary", {{"kind", quoted("sdof")}, {"mass", mass}, {"stiffness", stiffness}, {"damping_ratio", damping_ratio}});
  }
  // A key of [output].
  CaseText& output(const std::string& key, const Value& value) { return set("output", key, value); }

  // ---- the text ----
  std::string str() const {
    std::string s;
    for (const Table& t : tables_) {
      if (!s.empty()) s += "\n";
      s += t.array ? "[[" + t.name + "]]\n" : "[" + t.name + "]\n";
      for (const auto& [k, v] : t.keys) s += k + " = " + v + "\n";
    }
    return s;
  }
  operator std::string() const { return str(); }

 private:
  struct Table {
    std::string name;
    bool array = false;
    std::vector<std::pair<std::string, std::string>> keys;
  };
  CaseText& set_toml(const std::string& table, const std::string& key, const std::string& toml) {
    Table& t = table_named(table);
    for (auto& kv : t.keys)
      if (kv.first == key) {
        kv.second = toml;
        return *this;
      }
    t.keys.emplace_back(key, toml);
    return *this;
  }
  Table& table_named(const std::string& name) {
    for (Table& t : tables_)
      if (t.name == name && !t.array) return t;
    tables_.push_back({name, false, {}});
    return tables_.back();
  }
  std::vector<Table> tables_;
};

inline std::ostream& operator<<(std::ostream& o, const CaseText& c) { return o << c.str(); }

// ---- scenes several suites share ----

// 30 soft rubber balls (6 mm) with friction in a 40 x 40 x 50 mm box shaken at 2 mm, 25 Hz along
// (1, 0, 1), gravity, a settle of 0.02 s, for `duration`; frames every 5 ms, and checkpoints every
// `checkpoint_interval` when one is given (~1.3e-5 s steps).
inline std::string shaken_box(const std::string& duration, const std::string& checkpoint_interval = "") {
  CaseText c = CaseText()
                   .simulation(duration)
                   .set("simulation", "settle", "0.02 s")
                   .rubber()
                   .interactions(0.6, 0.4)
                   .box("rubber", "[0, 0, 0]", vec("40 mm", "40 mm", "50 mm"))
                   .harmonic("2 mm", "25 Hz", "[1, 0, 1]")
                   .balls("balls", "rubber", "6 mm", 30)
                   .set("particles.balls", {{"fill", quoted("random")}, {"seed", 7}})
                   .output("frame_interval", "5 ms");
  if (!checkpoint_interval.empty()) c.output("checkpoint_interval", checkpoint_interval);
  return c;
}

// The start of the steel scenes: [simulation] with `duration` under `gravity`, 200 GPa steel, and
// e 0.5, mu 0.3 for every pair.
inline CaseText steel_scene(const Value& duration, const Value& gravity = kGravityDown) {
  return CaseText().simulation(duration, gravity).steel().interactions(0.5, 0.3);
}

// A steel ball of `diameter` at the centre of a "planes" cavity (bounds +-10 mm) between two walls
// normal to x at -x_wall and x_wall (written with `digits`, see num()), no gravity, e 0.5, mu 0.3.
inline CaseText steel_ball_between_planes(const Value& duration, double x_wall, const Value& diameter, int digits = 0) {
  return steel_scene(duration, kNoGravity)
      .cavity("planes", "steel", "[-0.01, -0.01, -0.01]", "[0.01, 0.01, 0.01]")
      .plane(vec(num(-x_wall, digits), 0, 0), "[1, 0, 0]")
      .plane(vec(num(x_wall, digits), 0, 0), "[-1, 0, 0]")
      .placed("ball", "steel", diameter, "[[0, 0, 0]]");
}

// A 10-mm steel ball squeezed 10 um into each of two walls normal to x (so it follows the cavity),
// no gravity, initial overlaps allowed (1%), energy tallied; for `duration`. Written with 12 digits.
inline CaseText squeezed_ball(const Value& duration) {
  const double r = 5e-3, squeeze = 10e-6;
  return steel_ball_between_planes(duration, r - squeeze, num(2 * r, 12), 12)
      .set("simulation", "initial_overlap", 0.01)
      .output("energy", "true");
}

// An SDOF primary along x (mass, stiffness and damping ratio written with 12 digits) driven by a
// stepped sine of 0.5 N started steady (no refinement, steady within 1e-5, 8 cycles at least);
// `frequencies` are the excitation's frequency keys (frequencies, or around_modes, span, points).
inline CaseText steady_sdof_sweep(double mass, double stiffness, double damping_ratio, const CaseText::Keys& frequencies) {
  return CaseText()
      .sdof(num(mass, 12), num(stiffness, 12), num(damping_ratio, 12))
      .set("primary", {{"direction", "[1, 0, 0]"}, {"axis", "[0, 1, 0]"}})
      .set("excitation", {{"kind", quoted("stepped-sine")}, {"amplitude", "0.5 N"}})
      .set("excitation", frequencies)
      .set("excitation", {{"start", quoted("steady")}, {"refine", 0}, {"steady_tolerance", "1e-5"}, {"min_cycles", 8}});
}

// A 10-mm steel ball (softened to 2 GPa) on the floor of a 40 x 20 x 20 mm box, mu 0.3, gravity
// -z, on a 1-kg SDOF primary of 20 Hz (damping ratio 0.02) moving along x, swept over 18-22 Hz
// at 0.05 N.
// The box and its ball without the structure: a steel ball (2 GPa) of `diameter` resting on the
// floor (its centre `z`) of the 40 x 20 x 20 mm box, mu 0.3, settling 0.05 s.
inline CaseText ball_on_floor(const Value& diameter, const Value& z) {
  CaseText c;
  c.simulation("0.1 s")
      .set("simulation", "settle", "0.05 s")
      .steel("2 GPa")
      .interactions(0.5, 0.3)
      .box("steel", "[\"-20 mm\", \"-10 mm\", \"-10 mm\"]", "[\"20 mm\", \"10 mm\", \"10 mm\"]")
      .placed("ball", "steel", diameter, "[[0, 0, " + z.toml + "]]");
  return c;
}

inline std::string ball_on_sdof_floor() {
  return ball_on_floor("10 mm", "-4.99 mm")
      .sdof("1 kg", "15791.367 N/m", 0.02)
      .set("primary", {{"direction", "[1, 0, 0]"}, {"axis", "[0, 1, 0]"}})
      .set("excitation", {{"kind", quoted("stepped-sine")}, {"amplitude", "0.05 N"}, {"frequencies", "[18, 20, 22]"}})
      .str();
}

// A 6-mm ball on the floor of the box (ball_on_floor) on a light pinned-pinned beam: 1 m, 0.02 kg/m, EI 3.2423 N m^2 (modes 1 and 2 at 20 and 80 Hz), damping ratio 0.02,
// driven by 1 mN at 0.13 m (Gamma at most about 0.2 where a box sits: the ball rolls, mu 0.3).
inline std::string rolling_balls_on_beam() {
  return ball_on_floor("6 mm", "-6.99 mm")
      .set("primary", {{"kind", quoted("beam")}, {"length", quoted("1 m")}, {"youngs_modulus", "3.24228"}, {"second_moment", "1"},
                       {"line_density", quoted("0.02 kg/m")}, {"ends", quoted("pinned-pinned")}, {"modes", "3"}, {"damping_ratio", "0.02"},
                       {"attach", quoted("0.2 m")}, {"force_at", quoted("0.13 m")}, {"response_at", quoted("0.13 m")},
                       {"direction", "[1, 0, 0]"}, {"axis", "[0, 1, 0]"}})
      .set("excitation", {{"kind", quoted("stepped-sine")}, {"amplitude", quoted("1 mN")}, {"frequencies", "[17, 20, 23, 68, 80, 92]"},
                          {"min_cycles", "4"}, {"reduce_cycles", "4"}, {"max_cycles", "30"}})
      .str();
}

// An impact damper on an SDOF primary: a 10-mm steel ball (8% of the 0.05-kg primary) with 0.2 mm
// of clearance each side, swept over 27-33 Hz around the 30-Hz mode (damping ratio 0.02). One ball
// placed where it starts is deterministic (the seeds change nothing). Its peak reduction falls
// steadily from 8.3 dB at 0.03 N to 0.4 dB at 0.2 N (4.6 dB at 0.06 N); a run takes about a second.
// `c` is steel_ball_between_planes("0.1 s", 0.0052, "0.01") with any law set.
inline CaseText& impact_damper_on_sdof(CaseText& c) {
  return c.set("simulation", "settle", "2 ms")
      .placed("ball", "steel", "0.01", "[[0.0001, 0, 0]]", "[[0.05, 0, 0]]")
      .sdof(0.05, "1776.5287921960843", 0.02)
      .set("primary", {{"direction", "[1, 0, 0]"}, {"axis", "[0, 1, 0]"}})
      .set("excitation", {{"kind", quoted("stepped-sine")}, {"amplitude", "0.05 N"}, {"frequencies", "[27, 29, 30, 31, 33]"},
                          {"refine", 1}, {"min_cycles", 4}, {"reduce_cycles", 4}, {"max_cycles", 40}, {"chains", 1}});
}

inline std::string impact_damper_sdof() {
  CaseText c = steel_ball_between_planes("0.1 s", 0.0052, "0.01");
  return impact_damper_on_sdof(c).str();
}

}  // namespace bagdem::testing
