// results.h5: the HDF5 file a run writes as it goes, and the XDMF file beside it.
//
// Layout (all SI; every dataset has a "unit" string attribute; times in s):
//   /                      attributes: program_version, case_file, resolved_config (TOML text),
//                          status ("running", "complete", "failed: <message>"; "interrupted" when
//                          SIGINT/SIGTERM stopped the run), settle_end (s)
//   /particles/radius      [N]            m
//   /particles/material    [N]            int (index into the attribute "materials", comma list)
//   /frames/time           [F]            s
//   /frames/position       [F, N, 3]      m
//   /frames/velocity       [F, N, 3]      m/s
//   /frames/angular_velocity [F, N, 3]    rad/s
//   /cavity/time           [S]            s   middle of each sample interval (mean of its step times)
//   /cavity/position       [S, 3]         m   cavity displacement, mean over the interval
//   /cavity/velocity       [S, 3]         m/s cavity velocity, mean over the interval
//   /cavity/force          [S, 3]         N   force the contents exert on the cavity, mean over the
//                                             interval (impulse / interval), no gravity
//   /cavity/torque         [S, 3]         N m same, about the cavity reference point
//   /cavity/contents_velocity [S, 3]      m/s velocity of the contents' centre of mass (balls and
//                                             film) relative to the cavity, at the end of the
//                                             interval (time + interval/2): impacts' restitution
//                          attribute "interval" (s)
//   /energy/time           [E]            s
//   /energy/<name>         [E]            J   for name in kEnergyTerms (below)
//   /film/triangles        [T, 3]         int (unit "1") a bag run's film: node indices of its
//                                             triangles, counter-clockwise seen from outside
//   /film/position         [F, V, 3]      m   the film's V nodes at each frame of /frames/time
//   /structure/<column>    [S]                a run with a primary structure, at the cavity samples'
//                                             times (run/runner.cpp lists the columns and units)
//   /sweep/<column>        [P]                a stepped-sine sweep, one row per frequency
//                                             (run/stepped_sine.hpp lists the columns and units)
// Datasets are chunked and extendible; the file is flushed after each frame so that a killed run
// leaves a readable file. Resume truncates every time series to the lengths the checkpoint recorded
// and verifies what is left against the checkpoint's digest (a CRC-32 per dataset).
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "bagdem/vec3.hpp"

namespace bagdem {

// The energy budget's terms, each a dataset /energy/<name> (J), in the order of the values
// append_energy takes (step/energy.hpp: EnergySample::terms()).
inline constexpr std::array<const char*, 8> kEnergyTerms = {
    "kinetic", "elastic", "work_cavity", "work_gravity", "dissipated_normal", "dissipated_tangential",
    "dissipated_rolling", "dissipated_damping"};

// Lengths of the time series written so far, and a digest of the data they hold (stored in
// checkpoints; resume truncates to them and verifies the digest).
struct SeriesLengths {
  std::size_t frames = 0, cavity = 0, energy = 0, structure = 0;
  std::uint64_t digest = 0;  // CRC-32 over every dataset but /sweep, and the datasets' count
};

// A column of a table of scalars (append_table_row).
struct TableColumn {
  const char* name;
  const char* unit;
};

class ResultsFile {
 public:
  // Creates a new file (truncating any) at `path`. `materials` names the material indices.
  ResultsFile(const std::string& path, const std::vector<double>& radius,
              const std::vector<int>& material, const std::vector<std::string>& materials,
              double cavity_interval);
  // Reopens an existing file to continue a run: every series is cut to `lengths`; tables other than
  // /structure (/sweep) are removed, for their writer to write again from the rows it restored.
  // The data kept must match lengths.digest (what lengths() gave when the checkpoint was taken):
  // otherwise InputError naming the file (it was changed or damaged since).
  static ResultsFile reopen(const std::string& path, const SeriesLengths& lengths);
  ResultsFile(ResultsFile&&) noexcept;
  ResultsFile& operator=(ResultsFile&&) noexcept;
  ResultsFile(const ResultsFile&) = delete;
  ~ResultsFile();  // closes the file

  void set_attribute(const std::string& name, const std::string& value);
  void set_attribute(const std::string& name, double value);

  void append_frame(double t, const std::vector<Vec3>& position, const std::vector<Vec3>& velocity,
                    const std::vector<Vec3>& angular_velocity);
  // A bag run: writes /film/triangles and creates /film/position for `nodes` film nodes. Call it
  // before the first frame; on a file that already has the film (reopened) it only checks that
  // it is the same. Throws std::invalid_argument for a node index out of range or a film other
  // than the file's, std::logic_error when frames were written without a film.
  void write_film(const std::vector<std::array<std::uint32_t, 3>>& triangles, std::size_t nodes);
  // The film's nodes at the frame just appended: call it right after each append_frame (which
  // throws std::logic_error when the previous frame has no film frame). Flushes the file.
  void append_film_frame(const std::vector<Vec3>& position);

  void append_cavity(double t, const Vec3& position, const Vec3& velocity, const Vec3& mean_force,
                     const Vec3& mean_torque, const Vec3& contents_velocity);
  void append_energy(double t, const std::array<double, kEnergyTerms.size()>& terms);
  // A row of the table /<group>, one 1-D dataset per column (created, with its "unit" attribute,
  // by the first row; later rows must give the same columns). /structure is cut to
  // SeriesLengths::structure on reopening.
  void append_table_row(const std::string& group, const std::vector<TableColumn>& columns,
                        const std::vector<double>& values);

  // A dataset of the file as written so far (e.g. "/structure/displacement"), flattened row-major.
  std::vector<double> read_series(const std::string& dataset) const;

  SeriesLengths lengths() const;
  void flush();
  // A complete run's seal: each series appended to is stamped with the CRC-32 of its values
  // (attribute "crc32"), which every reader checks (h5::read_doubles): a file damaged or edited
  // afterwards is refused where its data are read, not reduced.
  void seal();
  void close();  // idempotent

 private:
  struct Impl;
  Impl* impl_ = nullptr;
  explicit ResultsFile(Impl* impl);
};

// Writes an XDMF 3 file at `xmf_path` that lets ParaView open the particle frames of the HDF5 file
// `h5_name` (a path relative to the XDMF file): a temporal collection of polyvertex grids with
// attributes velocity, angular_velocity, radius and material. `times` are the frame times.
// With a film (film_nodes and film_triangles > 0: the sizes given to write_film), each time step
// is instead a spatial collection of two grids: "particles" (as above) and "film" (triangles, its
// nodes at that frame).
void write_xdmf(const std::string& xmf_path, const std::string& h5_name, std::size_t n_particles,
                const std::vector<double>& times, std::size_t film_nodes = 0,
                std::size_t film_triangles = 0);

}  // namespace bagdem
