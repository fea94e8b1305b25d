#pragma once
// The definitions of Simulation<Physics>, instantiated by simulation.cpp (elastic physics) and
// simulation_plastic.cpp (physics with internal variables): two translation units that build in
// parallel, and elastic runs compiled as before the plastic physics existed.

#include "solver/simulation.hpp"

#include "solver/checkpoint.hpp"
#include "solver/installation.hpp"
#include "solver/output.hpp"
#include "solver/stepping_method_impl.hpp"
#include "solver/vtk_output.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <limits>
#include <numeric>
#include <sstream>
#include <unistd.h>
#include <utility>

namespace dgmpm {

namespace {

// Particles sorted by cell so that the per-cell loops read contiguous memory.
template <class ParticleSet>
void sort_by_cell(const Grid<ParticleSet::dim>& grid, ParticleSet& particles) {
  std::vector<int> cell(particles.size());
  Eigen::Matrix<double, ParticleSet::dim, 1> xi;
  for (int p = 0; p < particles.size(); ++p) cell[p] = grid.locate(particles.position.col(p), xi);
  std::vector<int> order(particles.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return cell[a] < cell[b]; });
  particles = particles.select(order);
}

const char* signal_name(int signal) {
  switch (signal) {
    case SIGTERM:
      return "SIGTERM";
    case SIGINT:
      return "SIGINT";
    case SIGHUP:
      return "SIGHUP";
    default:
      return "a signal";
  }
}

template <int Dim>
std::string grid_extent(const Grid<Dim>& g) {
  std::ostringstream s;
  for (int a = 0; a < Dim; ++a) s << (a ? " x [" : "[") << g.origin[a] << ", " << g.upper(a) << "]";
  return s.str();
}

}  // namespace
template <class Physics>
Simulation<Physics>::Simulation(const scene::Scene& scene, Communicator* ranks)
    : Simulation(scene, ranks, std::chrono::steady_clock::now()) {}

template <class Physics>
Simulation<Physics>::Simulation(const scene::Scene& scene, Communicator* ranks,
                                std::chrono::steady_clock::time_point start)
    : scene_(scene), problem_(make_problem<Physics>(scene)),
      blow_up_(scene.time.blow_up_check, scene.time.blow_up_factor) {
  sort_by_cell(problem_.grid, problem_.particles);
  total_particles_ = problem_.particles.size();
  total_cells_ = problem_.grid.num_cells();
  max_speed_ = problem_.max_wave_speed();
  if (scene_.particles_move) {  // initial positions: the displacement, the exact solution's
    problem_.particles.tracks_reference = true;
    problem_.particles.reference = problem_.particles.position;
  }
  method_ = make_method<Physics>({scene_, problem_, halo_, warnings_, max_speed_});
  warn_about_untouched_loads();
  if (ranks && ranks->size() > 1) distribute(*ranks);
  blow_up_.start(energy());
  setup_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// Set up on the whole scene (so the time step and the warnings are the serial run's), then
// keeps this rank's window: its particles, its grid and boundaries, a stepper on them.
template <class Physics>
void Simulation<Physics>::distribute(Communicator& ranks) {
  const std::string count = std::to_string(ranks.size()) + " MPI ranks";
  method_->check_distributable(count);
  const auto& grid = problem_.grid;
  const std::vector<int> dims =
      ranks.cartesian_layout(std::vector<bool>(grid.periodic.begin(), grid.periodic.end()),
                             std::vector<int>(grid.cells.begin(), grid.cells.end()));
  typename BlockDecomposition<dim>::Index layout{};
  std::copy(dims.begin(), dims.end(), layout.begin());
  // One ghost layer per stage.
  const int depth = traits(scene_.time.integrator).stages;
  try {
    halo_ = std::make_unique<Halo<ParticleSet>>(
        ranks, Subdomain<dim>(grid, BlockDecomposition<dim>(grid, layout), ranks.rank(), depth));
  } catch (const std::invalid_argument& e) {
    throw scene::SceneError(scene_.source + ": grid: cannot be split over " + count + ": " +
                            e.what());
  }
  problem_.particles = halo_->distribute(problem_.particles);
  problem_.boundaries = halo_->subdomain().boundaries(problem_.boundaries);
  problem_.grid = halo_->subdomain().window();
  method_->distributed();
}

template <class Physics>
Simulation<Physics>::~Simulation() = default;

template <class Physics>
void Simulation<Physics>::step(double dt) {
  step_speed_ = max_speed_;
  bool finite = false;  // known finite (DGMPM checks as it writes the particles)
  try {
    finite = method_->step(steps_ + 1, time_, dt);
  } catch (const ParticleOutsideGrid& e) {
    throw std::runtime_error(format_step(steps_ + 1, time_ + dt) + ": " + e.what() + " " +
                             grid_extent(full_grid()));
  }
  time_ += dt;
  ++steps_;
  // With finite states, positions moved by dt v are finite or outside the grid (thrown above).
  if (!finite) check_finite();
  method_->after_step(steps_, time_, dt);
  if (blow_up_.due()) check_growth();
}

// Unbounded growth (BlowUpMonitor): names the particle holding the most energy.
template <class Physics>
void Simulation<Physics>::check_growth() {
  const double reference = blow_up_.reference(method_->load_work());
  const double e = energy();
  if (!blow_up_.exceeds(e, reference)) return;
  const auto& p = problem_.particles;
  int worst = 0;
  double most = -1;
  const int n = owned_particles();
  for (int i = 0; i < n; ++i)
    if (const double ei = particle_energy(i).total(); ei > most) most = ei, worst = i;
  // Distributed: the rank holding the largest says where; the others stop.
  if (halo_ && halo_->comm().min(-most) != -most)
    throw RankStopped("the run is unstable (another rank names the particle)");
  Eigen::Matrix<double, dim, 1> xi;
  const int cell = full_grid().locate(p.position.col(worst), xi);
  std::ostringstream s;
  s << format_step(steps_, time_) << ": the run is unstable: energy " << std::setprecision(6) << e
    << ' ' << energy_unit(dim) << " is " << e / reference
    << " times the initial energy plus the work of the loads (" << reference
    << " J; time.blow_up_factor " << blow_up_.factor() << "); largest on particle " << p.id[worst]
    << " (x = " << p.position.col(worst).transpose() << ", cell " << cell << ", " << most << ' '
    << energy_unit(dim) << "). Lower the Courant number (or raise "
    << "time.blow_up_factor, or set time.blow_up_check false to run on)";
  throw std::runtime_error(s.str());
}

template <class Physics>
void Simulation<Physics>::check_finite() const {
  const auto& particles = problem_.particles;
  const int n = owned_particles();
  if (particles.state.leftCols(n).allFinite()) return;
  for (int p = 0; p < n; ++p) {
    if (particles.state.col(p).allFinite() && particles.position.col(p).allFinite()) continue;
    Eigen::Matrix<double, dim, 1> xi;
    const int cell = full_grid().locate(particles.position.col(p), xi);
    std::ostringstream s;
    s << format_step(steps_, time_) << ": non-finite state on particle " << particles.id[p]
      << " (x = " << particles.position.col(p).transpose() << ", cell " << cell
      << "); the run is unstable: lower the Courant number";
    throw std::runtime_error(s.str());
  }
}

template <class Physics>
double Simulation<Physics>::step_towards(double target) {
  const double remaining = target - time_;
  const double full = dt();
  if (remaining <= 1e-12 * full) {
    time_ = std::max(time_, target);
    return 0.0;
  }
  // The last step absorbs round-off rather than leaving a sliver step behind.
  const bool last = remaining <= full * (1 + 1e-9);
  const double length = last ? remaining : full;
  step(length);
  if (last) time_ = target;
  return length;
}

template <class Physics>
void Simulation<Physics>::advance_to(double t_end) {
  while (step_towards(t_end) > 0.0) {
  }
}

template <class Physics>
typename Simulation<Physics>::Field Simulation<Physics>::physical_state() const {
  const auto& p = problem_.particles;
  Field s(ncomp, owned_particles());
  for (int i = 0; i < s.cols(); ++i)
    s.col(i) = Physics::physical(p.state.col(i), problem_.materials[p.material[i]]);
  return s;
}

template <class Physics>
typename Simulation<Physics>::Energy Simulation<Physics>::energy_parts() const {
  // Sums over fixed blocks of particles (on threads), then of the blocks in order: the same bits
  // whatever the number of threads, and a run of one block sums as a serial loop does.
  const auto add = [](Energy& to, const Energy& e) {
    to.kinetic += e.kinetic;
    to.elastic += e.elastic;
    to.stored += e.stored;
    to.dissipated += e.dissipated;
  };
  const int n = owned_particles();
  const int blocks = (n + kEnergyBlock - 1) / kEnergyBlock;
  energy_blocks_.assign(static_cast<std::size_t>(blocks), Energy{});  // capacity kept
#pragma omp parallel for schedule(static) if (blocks > 1)
  for (int b = 0; b < blocks; ++b) {
    Energy& sum = energy_blocks_[static_cast<std::size_t>(b)];
    for (int i = b * kEnergyBlock; i < std::min(n, (b + 1) * kEnergyBlock); ++i)
      add(sum, particle_energy(i));
  }
  Energy e;
  for (const Energy& block : energy_blocks_) add(e, block);
  if (halo_) {
    std::array<double, 4> sums{e.kinetic, e.elastic, e.stored, e.dissipated};
    halo_->comm().sum(sums);
    e = {sums[0], sums[1], sums[2], sums[3]};
  }
  return e;
}

template <class Physics>
typename Simulation<Physics>::Energy Simulation<Physics>::particle_energy(int i) const {
  const auto& p = problem_.particles;
  const auto& m = problem_.materials[p.material[i]];
  Energy e{p.mass[i] * Physics::kinetic_energy_per_mass(p.state.col(i)), 0.0};
  // Where the elastic energy depends on the internal variables (plane strain's sigma_zz under
  // plastic flow), the physics says so by taking them.
  if constexpr (requires {
                  Physics::elastic_energy_per_mass(p.state.col(i), p.internal.col(i), m);
                })
    e.elastic = p.mass[i] * Physics::elastic_energy_per_mass(p.state.col(i), p.internal.col(i), m);
  else
    e.elastic = p.mass[i] * Physics::elastic_energy_per_mass(p.state.col(i), m);
  if constexpr (dissipative) {
    e.stored = p.mass[i] * Physics::stored_energy_per_mass(p.internal.col(i), m);
    e.dissipated = p.mass[i] * Physics::dissipated_energy_per_mass(p.internal.col(i));
  }
  return e;
}

template <class Physics>
typename Simulation<Physics>::Field Simulation<Physics>::exact_state(double t) const {
  const auto& p = problem_.particles;
  Field s(ncomp, owned_particles());
  const auto& x0 = p.tracks_reference ? p.reference : p.position;
  for (int i = 0; i < s.cols(); ++i) s.col(i) = problem_.exact(x0.col(i), t);
  return s;
}

// One row per particle, in the serial run's order (a distributed run gathers its ranks' owned
// particles on rank 0, which writes): the same file whatever the number of ranks.
template <class Physics>
void Simulation<Physics>::write_particles(const std::string& path) const {
  const Field s = physical_state();
  std::optional<Field> ex;
  if (problem_.exact) ex = exact_state(time_);
  const auto& p = problem_.particles;
  // Columns: id, position, mass, volume, physical state, internal variables, the physics' derived
  // outputs, exact state, displacement (moving particles).
  constexpr int kMass = 1 + dim, kVolume = 2 + dim, kState = 3 + dim;
  constexpr int kInternal = kState + ncomp, kDerived = kInternal + ParticleSet::n_internal;
  constexpr int kExact = kDerived + derived_count;
  const int kDisplacement = kExact + (ex ? ncomp : 0);
  // Total Lagrangian physics: the current position X + u after the reference X ("x").
  constexpr bool current = physics::CarriesDisplacement<Physics>;
  const int kCurrent = kDisplacement + (p.tracks_reference ? dim : 0);
  Eigen::MatrixXd table(kCurrent + (current ? dim : 0), s.cols());
  for (Eigen::Index i = 0; i < s.cols(); ++i) {
    table(0, i) = p.id[i];
    table.col(i).segment<dim>(1) = p.position.col(i);
    table(kMass, i) = p.mass[i];
    table(kVolume, i) = p.volume[i];
    table.col(i).segment<ncomp>(kState) = s.col(i);
    table.col(i).segment<ParticleSet::n_internal>(kInternal) = p.internal.col(i);
    if constexpr (derived_count > 0) {
      const auto d =
          Physics::derived(s.col(i), p.internal.col(i), problem_.materials[p.material[i]]);
      for (int k = 0; k < derived_count; ++k) table(kDerived + k, i) = d[k];
    }
    if (ex) table.col(i).segment<ncomp>(kExact) = ex->col(i);
    if (p.tracks_reference)
      table.col(i).segment<dim>(kDisplacement) = p.position.col(i) - p.reference.col(i);
    if constexpr (current)
      table.col(i).segment<dim>(kCurrent) =
          p.position.col(i) + Physics::displacement_of(p.internal.col(i));
  }
  if (halo_) table = halo_->gather(table);
  if (!root()) return;
  output::write_atomically(path, [&](std::ostream& out) {
    out << (dim == 1 ? "id,x,mass" : "id,x,y,mass,volume");
    for (const char* name : Physics::state_names) out << ',' << name;
    for (const char* name : Physics::internal_names) out << ',' << name;
    if constexpr (derived_count > 0)
      for (const char* name : Physics::derived_names) out << ',' << name;
    if (ex)
      for (const char* name : Physics::state_names) out << ",exact_" << name;
    if (p.tracks_reference) out << (dim == 1 ? ",displacement" : ",displacement_x,displacement_y");
    if (current) out << (dim == 1 ? ",current_x" : ",current_x,current_y");
    out << ",time\n";
    for (Eigen::Index i = 0; i < table.cols(); ++i) {
      out << static_cast<long>(table(0, i));
      for (int r = 1; r < table.rows(); ++r)
        if (dim > 1 || r != kVolume) {  // 1D rows have no volume
          out.put(',');
          output::write_number(out, table(r, i));
        }
      out.put(',');
      output::write_number(out, time_);
      out.put('\n');
    }
  });
}

namespace {
// particles_NNN.EXT: the k-th output (what a run writes and what its manifest lists).
std::string particle_file(std::size_t k, const char* ext) {
  char name[64];
  std::snprintf(name, sizeof name, "particles_%03zu.%s", k, ext);
  return name;
}
// A distributed run's checkpoint: rank 0 writes `name`, rank R > 0 its piece name_rR.ckpt.
std::string checkpoint_piece(const std::string& name, int rank) {
  if (rank == 0) return name;
  const std::string stem = name.substr(0, name.size() - std::string(".ckpt").size());
  return stem + "_r" + std::to_string(rank) + ".ckpt";
}
// particles_NNN_rR.vtu: rank R's piece of the k-th output of a distributed run.
std::string piece_file(std::size_t k, int rank) {
  char name[64];
  std::snprintf(name, sizeof name, "particles_%03zu_r%d.vtu", k, rank);
  return name;
}
}  // namespace

// The particles' .vtu `name` (serial), or (distributed) this rank's piece of output k, and on
// rank 0 the .pvtu `name` that opens the pieces as one data set.
template <class Physics>
void Simulation<Physics>::write_vtu(std::size_t k, const std::string& directory,
                                    const std::string& name) const {
  const auto& p = problem_.particles;
  const Field s = physical_state();
  const auto ex = problem_.exact ? std::optional(exact_state(time_)) : std::nullopt;
  const vtk::VtuOptions options{scene_.output.vtu_binary, time_};
  if (!halo_) {
    vtk::write_particles<Physics>(directory + "/" + name, p, problem_.materials, s, ex, options);
    return;
  }
  std::vector<int> owned(owned_particles());
  std::iota(owned.begin(), owned.end(), 0);
  const ParticleSet piece = p.select(owned);
  const auto data = vtk::point_data<Physics>(piece, problem_.materials, s, ex);
  Communicator& comm = halo_->comm();
  vtk::write_points(directory + "/" + piece_file(k, comm.rank()),
                    vtk::current_positions<Physics>(piece), data, options);
  comm.barrier();  // every piece complete before the index names it
  if (!root()) return;
  std::vector<std::string> pieces;
  for (int r = 0; r < comm.size(); ++r) pieces.push_back(piece_file(k, r));
  vtk::write_piece_index(directory + "/" + name, pieces, data);
}

// What one call of run() writes and where: the output directory's claim, the files planned, the
// energy history (written under its own name as the run goes, whole rows at a time: at every
// output and checkpoint and every few seconds, so that a killed run leaves its history to the
// last of them; a restart cuts it back to its checkpoint's rows).
template <class Physics>
struct Simulation<Physics>::RunRecord {
  RunRecord(const RunOptions& run_options, std::string output_directory)
      : options(run_options), directory(std::move(output_directory)) {}
  const RunOptions& options;
  std::string directory;
  bool writes = false, checkpoints = false;
  std::optional<output::DirectoryClaim> claim;
  std::vector<std::string> planned;
  output::CommittedFile committed;
  std::ostream* history = nullptr;  // rank 0's energy history, if written
  std::chrono::steady_clock::time_point last_commit = std::chrono::steady_clock::now();
  double next_checkpoint_time = std::numeric_limits<double>::infinity();
};

namespace detail {
// max_wave_speed (speeds that change with the state): the largest particle speed at the step's
// start, the one its dt was chosen with.
inline std::string history_header(bool dissipative, bool speeds) {
  std::string h = dissipative ? "step,time,dt,kinetic,elastic,stored,dissipated,total,boundary_work"
                              : "step,time,dt,kinetic,elastic,total,boundary_work";
  return h + (speeds ? ",max_wave_speed\n" : "\n");
}
}  // namespace detail

// A checkpoint's files: one, or one per rank.
template <class Physics>
std::vector<std::string> Simulation<Physics>::checkpoint_files(const std::string& name) const {
  std::vector<std::string> files{name};
  for (int r = 1; halo_ && r < halo_->comm().size(); ++r)
    files.push_back(checkpoint_piece(name, r));
  return files;
}

// A distributed run's VTU outputs: a .pvtu and one piece per rank.
template <class Physics>
std::string Simulation<Physics>::vtu_file(std::size_t k) const {
  return particle_file(k, halo_ ? "pvtu" : "vtu");
}

// Claims the output directory for the files the run will write (and the checkpoints a restart
// keeps), and says where a restart's earlier outputs are when it writes elsewhere.
template <class Physics>
void Simulation<Physics>::claim_directory(RunRecord& record, bool resumed) {
  const auto& output_times = scene_.output.times;
  const bool csv = scene_.output.csv, vtu = scene_.output.vtu;
  if (record.writes) output::create_directories(record.directory);
  if (record.writes && root()) {
    for (std::size_t k = 0; k < output_times.size(); ++k) {
      if (csv) record.planned.push_back(particle_file(k, "csv"));
      if (vtu) record.planned.push_back(vtu_file(k));
      for (int r = 0; vtu && halo_ && r < halo_->comm().size(); ++r)
        record.planned.push_back(piece_file(k, r));
    }
    if (vtu && !output_times.empty()) record.planned.push_back("particles.pvd");
    if (!output_times.empty()) record.planned.push_back("outputs.csv");
    record.planned.push_back("energy.csv");
    record.planned.push_back("summary.json");
    std::vector<std::string> listed = record.planned;
    for (const auto& c : progress_.checkpoints)
      for (const auto& f : checkpoint_files(c)) listed.push_back(f);
    // A restart keeps the directory's later checkpoints of this run on its manifest (a later run
    // there removes them with the rest).
    std::error_code ec;
    if (resumed)
      for (const auto& e : std::filesystem::directory_iterator(record.directory, ec)) {
        const std::string name = e.path().filename().string();
        if (name.rfind("checkpoint_", 0) == 0 && e.path().extension() == ".ckpt" &&
            std::find(listed.begin(), listed.end(), name) == listed.end())
          listed.push_back(name);
      }
    record.claim.emplace(record.directory, scene_.source, listed, record.options.overwrite,
                         resumed);
  }
  if (record.writes && halo_) halo_->comm().barrier();  // the claim cleared the directory
  if (resumed) {
    std::error_code ec;
    const auto here = std::filesystem::weakly_canonical(record.directory, ec);
    if (!record.writes) {
      warnings_.push_back("restarted from " + restored_from_ +
                          " without an output directory: the " + std::to_string(progress_.outputs) +
                          " outputs written before the checkpoint and the energy history up to "
                          "it are in " +
                          restored_directory_);
    } else if (here != std::filesystem::weakly_canonical(restored_directory_, ec)) {
      // Into another directory: the earlier outputs and history are copied there, so that the
      // index, the .pvd and the summary list files that exist.
      int copied = 0;
      if (root()) copied = copy_earlier_outputs(record.directory);
      if (halo_) halo_->comm().barrier();
      warnings_.push_back("restarted from " + restored_from_ +
                          " into another directory: " + std::to_string(copied) + " files of the " +
                          std::to_string(progress_.outputs) +
                          " outputs before the checkpoint, and its energy history, copied from " +
                          restored_directory_);
    }
  }
}

// The files of the outputs written before the checkpoint (particles_NNN*, every rank's piece)
// and the energy history, from the checkpoint's directory into `directory`; how many outputs'
// files were copied.
template <class Physics>
int Simulation<Physics>::copy_earlier_outputs(const std::string& directory) const {
  namespace fs = std::filesystem;
  int copied = 0;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(restored_directory_, ec)) {
    const std::string name = e.path().filename().string();
    // particles_NNN.EXT or particles_NNN_rR.vtu with NNN before the checkpoint's outputs (the
    // whole number: output 1000 is not output 100's).
    bool earlier = name == "energy.csv";
    if (!earlier && name.rfind("particles_", 0) == 0) {
      const std::size_t digits = name.find_first_not_of("0123456789", 10);
      if (digits != std::string::npos && digits > 10 &&
          (name[digits] == '.' || name[digits] == '_'))
        earlier = std::stoul(name.substr(10, digits - 10)) < progress_.outputs;
    }
    if (!earlier) continue;
    fs::copy_file(e.path(), fs::path(directory) / name, fs::copy_options::overwrite_existing, ec);
    if (ec)
      throw std::runtime_error("cannot copy " + e.path().string() + " into " + directory + ": " +
                               ec.message());
    copied += name != "energy.csv";
  }
  return copied;
}

// Opens the energy history, continuing a restart's committed file where it matches the
// checkpoint. Energies are sums over the ranks: every rank computes them, rank 0 writes.
template <class Physics>
void Simulation<Physics>::open_history(RunRecord& record, bool resumed) {
  if (!record.writes) return;
  const std::string path = record.directory + "/energy.csv";
  Progress& done = progress_;
  const bool initial_row = !resumed || steps_ == 0;
  const Energy e = initial_row ? energy_parts() : Energy{};  // collective
  if (root() &&
      (!resumed || !record.committed.resume(path, done.history_bytes, done.history_hash))) {
    if (resumed)
      warnings_.push_back(path + " does not hold the energy history the checkpoint " +
                          "recorded: it restarts at step " + std::to_string(steps_));
    record.committed.create(path);
    record.committed.stream() << detail::history_header(dissipative, state_dependent_speed);
    if (initial_row) write_history(&record.committed.stream(), 0.0, e);
  }
  if (root()) {
    record.history = &record.committed.stream();
    commit_history(record);
  }
}

// Appends the history's rows written since the last commit to energy.csv (rank 0).
template <class Physics>
void Simulation<Physics>::commit_history(RunRecord& record) const {
  if (!record.history) return;
  record.committed.commit();
  record.last_commit = std::chrono::steady_clock::now();
}

template <class Physics>
void Simulation<Physics>::write_history(std::ostream* out, double dt, const Energy& e) const {
  if (!out) return;
  *out << steps_ << ',' << time_ << ',' << dt << ',' << e.kinetic << ',' << e.elastic << ',';
  if (dissipative) *out << e.stored << ',' << e.dissipated << ',';
  // MPM reports no boundary work (SteppingMethod::boundary_work): its column holds 0.
  *out << e.total() << ',' << method_->boundary_work().value_or(0.0);
  if (state_dependent_speed) *out << ',' << (steps_ > 0 ? step_speed_ : max_speed_);
  *out << '\n';
}

// The step count up front: a run that would need more than time.max_steps is refused.
template <class Physics>
double Simulation<Physics>::expected_steps() const {
  const double expected = std::ceil((scene_.time.end - time_) / dt()) + steps_;
  if (expected > static_cast<double>(scene_.time.max_steps)) {
    std::ostringstream s;
    s << scene_.source << ": time.end: value " << scene_.time.end << " needs about " << expected
      << " steps of " << dt() << " s, more than time.max_steps (" << scene_.time.max_steps
      << "); allowed: an end time within time.max_steps, or a larger time.max_steps";
    throw scene::SceneError(s.str());
  }
  return expected;
}

// Particle output k: its files and its row of outputs.csv.
template <class Physics>
void Simulation<Physics>::write_output(RunRecord& record) {
  Progress& done = progress_;
  const std::size_t k = done.outputs;
  std::ostringstream row;
  row.precision(17);
  row << k << ',' << time_ << ',';
  if (scene_.output.csv) {
    const std::string name = particle_file(k, "csv");
    write_particles(record.directory + "/" + name);
    done.files.push_back(name);
    row << name;
  }
  row << ',';
  if (scene_.output.vtu) {
    const std::string name = vtu_file(k);
    write_vtu(k, record.directory, name);
    done.files.push_back(name);
    done.series.emplace_back(time_, name);
    row << name;
  }
  done.index_rows.push_back(row.str());
  ++done.outputs;
  write_index(record);
  if (root()) commit_history(record);
}

// Output k is due once the run reaches its time (landing) or its nearest step (not landing).
template <class Physics>
bool Simulation<Physics>::output_due(const RunRecord& record) const {
  const auto& times = scene_.output.times;
  return record.writes && progress_.outputs < times.size() &&
         time_ >= times[progress_.outputs] - (scene_.output.land ? 0.0 : 0.5 * dt());
}

template <class Physics>
bool Simulation<Physics>::checkpoint_due(const RunRecord& record) const {
  const RunOptions& o = record.options;
  return record.checkpoints && steps_ > std::max(progress_.checkpoint_step, 0L) &&
         ((o.checkpoint_steps > 0 && steps_ % o.checkpoint_steps == 0) ||
          time_ >= record.next_checkpoint_time);
}

// Commits the energy history, writes this rank's checkpoint, lists it in the manifest and drops
// the oldest beyond checkpoint_keep.
template <class Physics>
void Simulation<Physics>::take_checkpoint(RunRecord& record) {
  Progress& done = progress_;
  if (root()) {
    commit_history(record);
    done.history_bytes = record.committed.bytes();
    done.history_hash = record.committed.hash();
  }
  done.checkpoint_step = steps_;
  char name[64];
  std::snprintf(name, sizeof name, "checkpoint_%09ld.ckpt", steps_);
  std::vector<std::string> kept = done.checkpoints;
  kept.push_back(name);
  std::vector<std::string> dropped;
  if (record.options.checkpoint_keep > 0)
    while (kept.size() > static_cast<std::size_t>(record.options.checkpoint_keep)) {
      dropped.push_back(kept.front());
      kept.erase(kept.begin());
    }
  done.checkpoints = kept;  // recorded in the checkpoint itself
  const int rank = halo_ ? halo_->comm().rank() : 0;
  write_checkpoint(record.directory + "/" + checkpoint_piece(name, rank));
  if (halo_) halo_->comm().barrier();  // every piece written before the manifest lists it
  if (root()) {
    std::vector<std::string> listed = record.planned;
    for (const auto& c : kept)
      for (const auto& f : checkpoint_files(c)) listed.push_back(f);
    record.claim->record(listed);
  }
  for (const auto& f : dropped)
    std::filesystem::remove(record.directory + "/" + checkpoint_piece(f, rank));
  if (time_ >= record.next_checkpoint_time)
    record.next_checkpoint_time = next_checkpoint_time(record);
}

template <class Physics>
double Simulation<Physics>::next_checkpoint_time(const RunRecord& record) const {
  const double every = record.options.checkpoint_seconds;
  return every > 0 ? (std::floor(time_ / every) + 1) * every
                   : std::numeric_limits<double>::infinity();
}

// A traction or velocity on a side, or on a segment of it, that no particle's cell reaches does
// nothing: said at set-up rather than left silent.
template <class Physics>
void Simulation<Physics>::warn_about_untouched_loads() {
  const auto& grid = problem_.grid;
  const auto& p = problem_.particles;
  static constexpr const char* sides[3][2] = {{"xmin", "xmax"}, {"ymin", "ymax"}, {"zmin", "zmax"}};
  Eigen::Matrix<double, dim, 1> xi;
  for (int a = 0; a < dim; ++a)
    for (int s = 0; s < 2; ++s)
      for (const scene::BoundarySpec& b : scene_.boundaries[a][s]) {
        const bool loads = b.kind == BoundaryKind::traction || b.kind == BoundaryKind::velocity;
        if (!loads ||
            std::all_of(b.values.begin(), b.values.end(), [](double v) { return v == 0; }))
          continue;
        bool reached = false;
        for (int i = 0; i < p.size() && !reached; ++i) {
          const auto cell = grid.unflatten(grid.locate(p.position.col(i), xi));
          if (cell[a] != (s == 0 ? 0 : grid.cells[a] - 1)) continue;
          reached = true;
          if (dim > 1 && b.has_range) {  // the cell must overlap the segment along the side
            const int t = 1 - a;
            const double lo = grid.origin[t] + cell[t] * grid.cell_size[t];
            reached = lo < b.range_hi && lo + grid.cell_size[t] > b.range_lo;
          }
        }
        if (!reached) {
          std::ostringstream w;
          w << "boundaries." << sides[a][s] << ": the " << to_string(b.kind) << " there does "
            << "nothing: no particle is in the cells along that side";
          if (dim > 1 && b.has_range)
            w << " within its range [" << b.range_lo << ", " << b.range_hi << "] m";
          w << " (a body that does not reach the grid's edge is loaded by nothing)";
          warnings_.push_back(w.str());
        }
      }
}

template <class Physics>
RunSummary Simulation<Physics>::run(const RunOptions& options) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  last_summary_.reset();
  const bool resumed = !restored_from_.empty();
  if (!resumed) {
    progress_.dt_min = progress_.dt_max = dt();
    progress_.courant_min = progress_.courant_max = dt() * courant_per_dt();
  }
  RunRecord record{options, options.output_directory.value_or(scene_.output.directory)};
  record.writes = !record.directory.empty();
  record.checkpoints = options.checkpoint_steps > 0 || options.checkpoint_seconds > 0;
  if (record.checkpoints && !record.writes)
    throw scene::SceneError(scene_.source +
                            ": checkpoints need an output directory (output.directory or --out)");
  claim_directory(record, resumed);
  open_history(record, resumed);
  const double expected = expected_steps();
  const bool progress = options.progress && root();
  const bool terminal = progress && ::isatty(STDERR_FILENO);
  if (terminal)
    std::fprintf(stderr, "%s: about %.0f steps of %.6g s\n", scene_.source.c_str(),
                 expected - steps_, dt());
  const auto seconds = [&] { return std::chrono::duration<double>(clock::now() - start).count(); };
  int stopped = 0;  // the signal that interrupted the run
  try {
    stopped = time_loop(record, progress);
    if (!stopped && scene_.time.blow_up_check) check_growth();  // runs shorter than its interval
    // An interrupted run with checkpoints on leaves one where it stopped, to go on from.
    if (stopped && record.checkpoints && steps_ > progress_.checkpoint_step)
      take_checkpoint(record);
  } catch (const std::exception& e) {
    if (terminal) std::fprintf(stderr, "\r%100s\r", "");
    record_failure(record, seconds(), e.what());
    throw;
  }
  if (terminal) std::fprintf(stderr, "\r%100s\r", "");
  RunSummary summary = summarise();
  if (stopped) {
    std::ostringstream reason;
    reason << format_step(steps_, time_) << ": stopped by signal " << stopped << " ("
           << signal_name(stopped) << ") before the end time " << scene_.time.end << " s";
    summary.status = "interrupted";
    summary.reason = reason.str();
  }
  summary.stepping_seconds = seconds();
  summary.wall_seconds = summary.setup_seconds + summary.stepping_seconds;
  close_record(record, summary);
  last_summary_ = summary;
  return summary;
}

// The steps to the end time with the outputs and checkpoints due on the way; returns 0 there, or
// the signal that asked the run to stop (after a whole step, every rank at the same one).
// `progress`: a line on stderr, rewritten twice a second on a terminal, a new line every
// options.progress_every seconds otherwise (a batch job's log), from 2 s (progress_every) into the
// loop: step, time, dt, the energy balance and the time left at the recent pace (simulated time per
// wall second over the last report interval, which follows a step that changes, as the run's
// average would not).
template <class Physics>
int Simulation<Physics>::time_loop(RunRecord& record, bool progress) {
  const bool terminal = progress && ::isatty(STDERR_FILENO);
  const double first = terminal ? 2.0 : record.options.progress_every;
  const auto every = terminal ? std::chrono::duration<double>(0.5)
                              : std::chrono::duration<double>(record.options.progress_every);
  const auto start = std::chrono::steady_clock::now();
  auto last_report = start;
  double last_report_time = time_;
  Energy energy{};
  const double t_end = scene_.time.end;
  const auto& output_times = scene_.output.times;
  record.next_checkpoint_time = next_checkpoint_time(record);
  for (;;) {
    while (output_due(record)) write_output(record);
    if (checkpoint_due(record)) take_checkpoint(record);
    double target = t_end;
    if (scene_.output.land && record.writes && progress_.outputs < output_times.size())
      target = std::min(target, output_times[progress_.outputs]);
    const double controlled = dt();
    const double dt = step_towards(target);
    if (dt == 0.0) {
      if (target >= t_end) return 0;
      continue;  // landed on an output time within round-off: written above
    }
    if (steps_ >= scene_.time.max_steps && time_ < t_end)
      throw std::runtime_error(format_step(steps_, time_) + ": time.max_steps (" +
                               std::to_string(scene_.time.max_steps) +
                               ") reached before the end time; the automatic step shrank "
                               "(raise time.max_steps to go on)");
    // The range of the controlled step; steps shortened to land on a time are not counted.
    progress_.dt_min = std::min(progress_.dt_min, controlled);
    progress_.dt_max = std::max(progress_.dt_max, controlled);
    const double courant = controlled * (step_speed_ / cell_size());  // speeds at the step's start
    progress_.courant_min = std::min(progress_.courant_min, courant);
    progress_.courant_max = std::max(progress_.courant_max, courant);
    if (record.writes) {
      energy = energy_parts();
      write_history(record.history, dt, energy);
      constexpr auto kCommitEvery = std::chrono::seconds(2);  // what a killed run loses at most
      if (record.history && std::chrono::steady_clock::now() - record.last_commit > kCommitEvery)
        commit_history(record);
    }
    if (const int signal = stop_signal(record.options)) return signal;
    if (progress) {
      const auto now = std::chrono::steady_clock::now();
      const double elapsed = std::chrono::duration<double>(now - start).count();
      if (elapsed > first && now - last_report > every) {
        const double window = std::chrono::duration<double>(now - last_report).count();
        const double pace = (time_ - last_report_time) / window;  // simulated s per wall s
        last_report = now;
        last_report_time = time_;
        const double left = pace > 0 ? (t_end - time_) / pace : 0.0;
        std::string balance;  // E - E0 - W over E0 + W, when the energy is computed
        if (record.writes && !terminal) {
          char text[64];
          const double work = method_->load_work(), e0 = blow_up_.initial_energy();
          std::snprintf(text, sizeof text, "  (E - E0 - W) / (E0 + W) %+.1e",
                        (energy.total() - e0 - work) / std::max(e0 + work, 1e-300));
          balance = text;
        }
        std::fprintf(stderr,
                     "%sstep %ld  t = %.6g / %.6g  (%.1f%%)  dt %.3g%s  about %.0f s left%s",
                     terminal ? "\r" : "", steps_, time_, t_end, 100.0 * time_ / t_end, dt,
                     balance.c_str(), left, terminal ? "   " : "\n");
      }
    }
  }
}

// The signal a handler recorded in options.stop, agreed over the ranks (0: none). A distributed
// run asks every 16 steps (a reduction; every rank counts the same steps).
template <class Physics>
int Simulation<Physics>::stop_signal(const RunOptions& options) const {
  if (!options.stop || (halo_ && steps_ % 16 != 0)) return 0;
  double signal = *options.stop;
  if (halo_) signal = -halo_->comm().min(-signal);
  return static_cast<int>(signal);
}

// A run that an error stops still leaves its record: the summary with status "failed" and the
// reason, the energy history so far, the outputs' index and series. In a distributed run the
// other ranks may be anywhere, so nothing collective is called: rank 0 writes what it knows (the
// summary's energies and errors are left out); an error met by another rank alone is reported
// on stderr only.
template <class Physics>
void Simulation<Physics>::record_failure(RunRecord& record, double stepping_seconds,
                                         const std::string& reason) {
  RunSummary s;
  if (!halo_) {
    s = summarise();
  } else {
    s.run = {{"version", version()},
             {"scene", scene_.source},
             {"dimension", dim},
             {"ranks", halo_->comm().size()}};
    s.steps = steps_;
    s.final_time = time_;
    s.warnings = warnings_;
    s.setup_seconds = setup_seconds_;
  }
  s.status = "failed";
  s.reason = reason;
  s.stepping_seconds = stepping_seconds;
  s.wall_seconds = s.setup_seconds + stepping_seconds;
  last_summary_ = s;
  if (!record.writes || !root()) return;
  try {
    close_record(record, *last_summary_);
  } catch (const std::exception&) {
    // The run's own error is what the caller reports; a record that cannot be written (a full
    // disk) must not replace it.
  }
}

// The run's numbers (collective in a distributed run; rank 0's are complete).
template <class Physics>
RunSummary Simulation<Physics>::summarise() const {
  RunSummary summary;
  summary.run = {{"version", version()},
                 {"scene", scene_.source},
                 {"method", scene::to_string(scene_.method)},
                 {"integrator", scene::to_string(scene_.time.integrator)},
                 {"dimension", dim},
                 {"particles", total_particles_},
                 {"cells", total_cells_}};
  if (halo_) {
    // The load balance of the block decomposition (void regions leave ranks idle).
    const std::vector<double> counts = halo_->comm().gather({double(owned_particles())});
    if (root()) {
      const double largest = *std::max_element(counts.begin(), counts.end());
      summary.run["ranks"] = counts.size();
      summary.run["particles_per_rank"] = std::vector<long>(counts.begin(), counts.end());
      summary.run["imbalance"] = largest * counts.size() / total_particles_;
    }
  }
  if (!restored_from_.empty()) summary.run["restarted_from"] = restored_from_;
  summary.energy_initial = blow_up_.initial_energy();
  summary.dt_min = progress_.dt_min;
  summary.dt_max = progress_.dt_max;
  summary.courant_min = progress_.courant_min;
  summary.courant_max = progress_.courant_max;
  summary.steps = steps_;
  summary.final_time = time_;
  summary.warnings = warnings_;
  // Where the method reports none (MPM): null in the summary rather than a zero that means nothing.
  summary.boundary_work =
      method_->boundary_work().value_or(std::numeric_limits<double>::quiet_NaN());
  const Energy final_energy = energy_parts();
  summary.energy_final = final_energy.total();
  if (dissipative) {
    summary.energy_stored = final_energy.stored;
    summary.energy_dissipated = final_energy.dissipated;
  }
  if (problem_.exact) add_errors(summary);
  summary.setup_seconds = setup_seconds_;
  method_->summarise(summary);
  return summary;
}

// Relative errors against the exact solution, over every rank's particles.
template <class Physics>
void Simulation<Physics>::add_errors(RunSummary& summary) const {
  const int n = owned_particles();
  Eigen::MatrixXd all(2 * ncomp + 1, n);  // computed, exact, volume: the serial run's sums
  all << physical_state(), exact_state(time_), problem_.particles.volume.head(n).transpose();
  if (halo_) all = halo_->gather(all);
  if (!root()) return;
  const Eigen::MatrixXd s = all.topRows(ncomp), ex = all.middleRows(ncomp, ncomp);
  const Eigen::VectorXd vol = all.bottomRows(1).transpose();
  // Where one exact field vanishes, the other one, through the impedance, sets the scale.
  const double z = problem_.exact_impedance;
  const Eigen::MatrixXd es = ex.topRows(ncomp - dim), ev = ex.bottomRows(dim);
  summary.stress_errors = relative_errors(s.topRows(ncomp - dim), es, vol, z * ev);
  summary.velocity_errors = relative_errors(s.bottomRows(dim), ev, vol, es / z);
}

// The outputs' index (outputs.csv) and ParaView series (.pvd) as they stand: rewritten at every
// output, so that a run stopped early leaves them matching its particle files.
template <class Physics>
void Simulation<Physics>::write_index(const RunRecord& record) const {
  const Progress& done = progress_;
  if (!record.writes || !root()) return;
  if (!done.index_rows.empty())
    output::write_atomically(record.directory + "/outputs.csv", [&](std::ostream& out) {
      out << "index,time,csv,vtu\n";
      for (const auto& r : done.index_rows) out << r << '\n';
    });
  if (scene_.output.vtu && !done.series.empty())
    vtk::write_series(record.directory + "/particles.pvd", done.series);
}

// The run's last files: the output index, the ParaView series, the energy history and the
// summary, listed in the summary with the particle files.
template <class Physics>
void Simulation<Physics>::close_record(RunRecord& record, RunSummary& summary) {
  const std::string& directory = record.directory;
  const Progress& done = progress_;
  for (const auto& name : done.files) summary.files.push_back(directory + "/" + name);
  if (!record.writes || !root()) return;
  write_index(record);
  if (!done.index_rows.empty()) summary.files.push_back(directory + "/outputs.csv");
  if (scene_.output.vtu && !done.series.empty())
    summary.files.push_back(directory + "/particles.pvd");
  commit_history(record);
  summary.files.push_back(directory + "/energy.csv");
  const std::string path = directory + "/summary.json";
  summary.files.push_back(path);
  const nlohmann::json j = summary.to_json();
  output::write_atomically(path, [&](std::ostream& out) { out << j.dump(2) << '\n'; });
}

namespace {
template <class M>
void put(checkpoint::PayloadWriter& w, const M& m) {
  w.bytes(m.data(), sizeof(*m.data()) * static_cast<std::size_t>(m.size()));
}
template <class M>
void get(checkpoint::PayloadReader& r, M& m) {
  r.bytes(m.data(), sizeof(*m.data()) * static_cast<std::size_t>(m.size()));
}
}  // namespace

template <class Physics>
void Simulation<Physics>::write_checkpoint(const std::string& path) const {
  using checkpoint::bits;
  // Distributed: this rank's owned particles and their places in the serial arrays.
  const int n = owned_particles();
  std::vector<int> first(n);
  std::iota(first.begin(), first.end(), 0);
  const ParticleSet owned = halo_ ? problem_.particles.select(first) : ParticleSet{};
  const ParticleSet& p = halo_ ? owned : problem_.particles;
  std::vector<long> global(halo_ ? n : 0);
  for (std::size_t i = 0; i < global.size(); ++i) global[i] = halo_->global_index(int(i));
  const Progress& d = progress_;
  nlohmann::json series = nlohmann::json::array();
  for (const auto& [t, name] : d.series) series.push_back({bits(t), name});
  checkpoint::File file;
  file.header = {
      {"format", checkpoint::kFormat},
      {"version", version()},
      {"scene_source", std::filesystem::absolute(scene_.source).lexically_normal().string()},
      {"scene", checkpoint::scene_identity(scene_)},
      {"dimension", dim},
      {"components", ncomp},
      {"particles", p.size()},
      {"step", steps_},
      {"time", bits(time_)},
      {"max_speed", bits(max_speed_)},
      {"warnings", warnings_},
      {"progress",
       {{"outputs", d.outputs},
        {"series", series},
        {"index_rows", d.index_rows},
        {"files", d.files},
        {"checkpoints", d.checkpoints},
        {"dt_min", bits(d.dt_min)},
        {"dt_max", bits(d.dt_max)},
        {"courant_min", bits(d.courant_min)},
        {"courant_max", bits(d.courant_max)},
        {"history_bytes", d.history_bytes},
        {"history_hash", d.history_hash},
        {"checkpoint_step", d.checkpoint_step}}}};
  method_->save(file.header);
  blow_up_.save(file.header);
  if (halo_) {
    file.header["ranks"] = halo_->comm().size();
    file.header["rank"] = halo_->comm().rank();
  }
  // Only where there are some: elastic checkpoints keep the header they always had.
  if (ParticleSet::n_internal > 0) file.header["internal_variables"] = ParticleSet::n_internal;
  checkpoint::PayloadWriter w(file.payload);
  p.for_each_field([&](const FieldInfo&, const auto& a) { put(w, a); });
  if (halo_) put(w, global);
  checkpoint::write(path, file);
}

template <class Physics>
void Simulation<Physics>::restore(const std::string& path) {
  using checkpoint::from_bits;
  // Distributed: each rank reads its piece (rank 0 the named file) of a run on as many ranks.
  const int rank = halo_ ? halo_->comm().rank() : 0, ranks = halo_ ? halo_->comm().size() : 1;
  const std::string piece = checkpoint_piece(path, rank);
  const checkpoint::File file = checkpoint::read(piece);
  const nlohmann::json& h = file.header;
  checkpoint::check_compatible(piece, h, scene_);
  auto& p = problem_.particles;
  try {
    if (h.value("ranks", 1) != ranks || h.value("rank", 0) != rank)
      throw scene::SceneError(piece + ": cannot restart from this checkpoint: it is rank " +
                              std::to_string(h.value("rank", 0)) + "'s of a run on " +
                              std::to_string(h.value("ranks", 1)) +
                              " rank(s); allowed: a restart " + "on as many ranks (mpirun -np " +
                              std::to_string(h.value("ranks", 1)) + ")");
    const int n = halo_ ? h.at("particles").get<int>() : p.size();
    if (h.at("dimension") != dim || h.at("components") != ncomp || h.at("particles") != n ||
        h.value("internal_variables", 0) != ParticleSet::n_internal || n < 0 ||
        n > total_particles_)
      throw scene::SceneError(
          piece + ": cannot restart from this checkpoint: it holds " + h.at("particles").dump() +
          " particles in " + h.at("dimension").dump() + "D with " +
          std::to_string(h.value("internal_variables", 0)) + " internal variables, the scene " +
          std::to_string(total_particles_) + " in " + std::to_string(dim) + "D with " +
          std::to_string(ParticleSet::n_internal));
    ParticleSet restored;
    restored.tracks_reference = p.tracks_reference;
    restored.resize(n);
    std::vector<long> global(halo_ ? n : 0);
    checkpoint::PayloadReader r(piece, file.payload);
    restored.for_each_field([&](const FieldInfo&, auto& a) { get(r, a); });
    if (halo_) get(r, global);
    r.expect_end();
    for (std::size_t i = 0; i < global.size(); ++i)
      if (global[i] < 0 || global[i] >= total_particles_ || (i > 0 && global[i] <= global[i - 1]))
        throw scene::SceneError(piece +
                                ": cannot restart from this checkpoint: corrupt particle order");
    for (int m : restored.material)
      if (m < 0 || m >= static_cast<int>(problem_.materials.size()))
        throw scene::SceneError(path + ": cannot restart from this checkpoint: corrupt material");
    const auto u = [&](const nlohmann::json& j, const char* key) {
      return from_bits(j.at(key).get<std::uint64_t>());
    };
    Progress d;
    const nlohmann::json& g = h.at("progress");
    d.outputs = g.at("outputs").get<std::size_t>();
    for (const auto& e : g.at("series"))
      d.series.emplace_back(from_bits(e.at(0).get<std::uint64_t>()), e.at(1).get<std::string>());
    d.index_rows = g.at("index_rows").get<std::vector<std::string>>();
    d.files = g.at("files").get<std::vector<std::string>>();
    d.checkpoints = g.at("checkpoints").get<std::vector<std::string>>();
    d.dt_min = u(g, "dt_min");
    d.dt_max = u(g, "dt_max");
    d.courant_min = u(g, "courant_min");
    d.courant_max = u(g, "courant_max");
    d.history_bytes = g.at("history_bytes").get<std::uint64_t>();
    d.history_hash = g.at("history_hash").get<std::uint64_t>();
    d.checkpoint_step = g.at("checkpoint_step").get<long>();
    // All read: the state changes only now.
    steps_ = h.at("step").get<long>();
    time_ = u(h, "time");
    max_speed_ = u(h, "max_speed");
    blow_up_.restore(h);
    warnings_ = h.at("warnings").get<std::vector<std::string>>();
    p = std::move(restored);
    if (halo_) halo_->restore(p, global);  // the ghosts, from their owners
    progress_ = std::move(d);
    method_->restore(h);
  } catch (const nlohmann::json::exception& e) {
    throw scene::SceneError(path +
                            ": cannot restart from this checkpoint: its header is "
                            "incomplete (" +
                            std::string(e.what()) + ")");
  }
  restored_from_ = path;
  restored_directory_ = std::filesystem::path(path).parent_path().string();
  if (restored_directory_.empty()) restored_directory_ = ".";
}

}  // namespace dgmpm
