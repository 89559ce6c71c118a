// From a case directory to a resolved Scene: parse case.toml (with --set overrides), validate every
// value, fill defaults, generate particles, choose the time step and decide what is modelled.
// Errors are InputError (exit code 2) naming file, key, value and what is allowed.
#pragma once
#include <string>
#include <vector>

#include "bagdem/case/case_reader.hpp"
#include "bagdem/scene.hpp"

namespace bagdem {

Scene load_case(const std::string& case_dir, const std::vector<std::string>& overrides = {});

// Where two resolved case texts (Scene::resolved) differ, key by key: "cavity.radius: was 0.01175,
// now 0.01; ..." (the first four, and how many more), the keys in `ignore` (and those under them)
// left out; "" when they are the same. Texts that are not TOML: the first differing line, as "was
// 'LINE', now 'LINE'". Used to refuse a resume, a reduction or a comparison with another case than
// the run's.
std::string case_differences(const std::string& was, const std::string& now, const std::vector<std::string>& ignore = {});

// Human-readable report of a resolved scene (what `bagdem check` prints).
std::string describe_scene(const Scene& s);

// The lines of describe_scene but the case's path and the memory estimate (a file the case reads is
// named as the case names it, relative to the case: a moved case is the same): what the run will
// compute, defaults and derived values included (the time step, the bending clock, what is
// modelled). A sweep's point.toml and a checkpoint record it, so that a bagdem that resolves the
// same case differently (another default) refuses to resume rather than mix its figures with the
// earlier ones. Two records differ where scene_difference is not "": "was 'LINE', now 'LINE'" for
// the first differing line.
std::vector<std::string> scene_record(const Scene& s);
std::string scene_difference(const std::vector<std::string>& was, const std::vector<std::string>& now);

// Decides s.models (tangential, rolling, rotation, gravity) from the pair laws that can occur.
void decide_models(Scene& s);

// ---- pieces of the resolution, one file each under src/case/ ----

// cavity_kinds.cpp: [cavity] -> walls, bounding box and reference point (table of kinds).
void resolve_cavity(const CaseReader& in, Scene& s, int material);

// particle_fill.cpp: [particles.<group>] -> ParticleInit list (explicit, file, or generated).
void resolve_particles(const CaseReader& in, Scene& s, const std::vector<std::string>& material_names);

// bag.cpp: [bag] -> Scene::bag (film, strings) and the bag's balls appended to Scene::particles.
void resolve_bag(const CaseReader& in, Scene& s, const std::vector<std::string>& material_names);
// bag.cpp, after the step is known: the film's bending clock (Bag::bending_interval).
void resolve_bending_clock(const CaseReader& in, Scene& s);

// dampers.cpp: [[dampers]] -> the other dampers' names and the keys each changes ("KEY=VALUE"
// overrides), checked: a damper may change its cavity, contents, materials and attachment only.
struct DamperKeys {
  std::string name;
  std::vector<std::string> set;
};
std::vector<DamperKeys> read_dampers(const CaseReader& in);
// dampers.cpp: the case's own damper s and the others (resolved at one step) made one structure:
// each Primary's mass matrix carries every cavity's mass; s.more_dampers takes the others.
void join_dampers(Scene& s, std::vector<Scene>& others, const std::vector<DamperKeys>& keys);
// dampers.cpp: whether a [[dampers]] entry may change `key` (its cavity, contents and where and how
// it is attached), and the list of those keys for messages.
bool damper_may_change(const std::string& key);
std::string damper_keys_text();
// A command that handles one damper refuses a case of several (InputError naming `dampers`, exit
// 2): `what` says what it does with one ("predicts with one damper's map").
void refuse_several_dampers(const Scene& s, const std::string& command, const std::string& what);
// A number as TOML text that reads back to the same double (%.17g).
std::string exact_text(double x);

// timestep.cpp: the time step (auto or explicit, checked against the critical step).
void resolve_timestep(const CaseReader& in, Scene& s);

}  // namespace bagdem

namespace bagdem {
// motion_kinds.cpp: [cavity.motion] -> Motion (table of kinds: fixed, harmonic, table).
void resolve_motion(const CaseReader& in, Scene& s);
// primary_kinds.cpp: [primary] and [excitation] -> Scene::primary (table of kinds: sdof, beam,
// fe-beam; none = prescribed motion).
void resolve_primary(const CaseReader& in, Scene& s);
}  // namespace bagdem
