// The resolved scene: what a case file becomes after parsing and validation. SI units, every
// default filled, and every "what is modelled" decision taken (src/case/load_case.cpp). The stepper
// and the recorders read only this.
#pragma once
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bagdem/bag/bag.hpp"
#include "bagdem/material.hpp"
#include "bagdem/motion/motion.hpp"
#include "bagdem/structure/primary.hpp"
#include "bagdem/vec3.hpp"
#include "bagdem/walls/mesh_wall.hpp"
#include "bagdem/walls/wall.hpp"

namespace bagdem {

struct ParticleInit {
  Vec3 x = Vec3::Zero();  // (unit: m)
  Vec3 v = Vec3::Zero();  // (unit: m/s)
  Vec3 w = Vec3::Zero();  // (unit: rad/s)
  double radius = 0;      // (unit: m)
  int material = 0;       // index into Scene::materials
};

// What the scene requires; anything false is not computed at all.
struct ModelSwitches {
  bool tangential = true;  // any pair with friction > 0: tangential springs with history
  bool rolling = false;    // any pair with rolling friction > 0
  bool rotation = true;    // tangential || rolling: integrate angular velocity
  bool gravity = true;     // gravity vector non-zero
  bool energy = true;      // energy budget tallies (output.energy)
};

struct OutputSettings {
  double frame_interval = 0;       // particle frames (unit: s); 0 = only first and last
  double cavity_interval = 0;      // cavity force/kinematics samples (unit: s)
  double energy_interval = 0;      // energy budget rows (unit: s)
  double checkpoint_interval = 0;  // checkpoints (unit: s); 0 = none
  double skip_cycles = 1;          // start-up cycles after settling left out of per-cycle figures
};

struct Scene;

// A damper besides the case's own on the same structure (case key [[dampers]], src/case/dampers.cpp):
// the whole case resolved again with the damper's keys changed (its cavity, contents and where it is
// attached). Its scene shares the structure (the same modes, force and masses: its Primary differs
// only in where the cavity is attached), the step, settle, duration and output settings.
struct Damper {
  std::string name;
  std::shared_ptr<const Scene> scene;
};

struct Scene {
  std::string case_dir;   // directory of the case
  std::string case_file;  // path of case.toml, for messages
  std::string resolved;   // the resolved configuration as TOML text (written to results.h5), the
                          // fingerprints of the files it reads at its end (CaseReader::text)
  std::map<std::string, std::string> files;  // those fingerprints: the case's key -> CaseReader::files()'s text
  std::map<std::string, std::string> defaults;  // the keys read with a default: key -> CaseReader::defaults()'s text

  std::vector<Material> materials;
  PairLawTable laws;
  std::vector<ParticleInit> particles;

  std::string cavity_kind;        // "box", "cylinder", "planes", "stl"
  std::vector<Wall> walls;        // in the cavity frame (at rest place)
  std::vector<MeshWall> mesh_walls;  // triangulated walls in the cavity frame (cavity kind "stl")
  std::vector<std::string> wall_names;  // one per wall, for messages ("box -x", "bore")
  Vec3 cavity_lo = Vec3::Zero();  // bounding box of the cavity at rest, low corner (unit: m)
  Vec3 cavity_hi = Vec3::Zero();  // high corner (unit: m)
  Vec3 cavity_reference = Vec3::Zero();  // point the cavity torque is taken about (unit: m)
  std::shared_ptr<const Motion> motion;  // motion time starts when settling ends

  std::shared_ptr<const Bag> bag;        // the bag (film, strings, its balls), or null
  // The primary structure carrying the cavity (structure/primary.hpp), or null: the cavity then
  // follows `motion`. With a primary, `motion` is fixed and the structure moves the cavity.
  std::shared_ptr<const Primary> primary;

  Vec3 gravity = Vec3::Zero();  // (unit: m/s^2)
  double settle = 0;            // settle phase before the measured part, cavity at rest (unit: s)
  double duration = 0;          // measured part (unit: s); total simulated = settle + duration
  double dt = 0;                // time step (unit: s)
  std::string dt_reason;        // how dt was chosen, for `check`
  std::vector<std::string> warnings;  // accepted but questionable settings, printed by check and run
  double dt_critical = 0;       // critical (stability) step of the stiffest contact (unit: s)
  double expected_speed = 0;    // expected maximum impact speed used for dt and checks (unit: m/s)

  ModelSwitches models;
  std::string broad_phase = "hash";
  double skin = 0;                     // Verlet skin (unit: m)
  double max_overlap_fraction = 0.1;   // run stops when an overlap exceeds this fraction of the radius
  double max_energy_error = 0.05;      // run stops when the energy budget is off by this fraction of its scale (0: never)
  std::uint64_t seed = 0;              // random seed (particle generation)
  OutputSettings output;

  // Several dampers on one structure: this scene's name among them and the others, in the case's
  // order (empty: the case's own damper alone). Only with a primary structure.
  std::string damper_name = "1";
  std::vector<Damper> more_dampers;

  std::uint64_t total_steps() const;   // ceil((settle + duration) / dt)
};

}  // namespace bagdem
