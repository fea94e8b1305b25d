#pragma once
// The particles of one rank of a distributed run (docs/distributed.md): those of its block
// (owned) and copies of those of its ghost layers, stepped together with the serial code; after
// each step the owners send the new states of the particles their partners hold as ghosts, so
// that every rank starts each step with the serial run's particles on its window.
//
// Local order: the owned particles, then the ghosts, each in the serial run's order (its global
// index). A cell's particles are all owned or all ghosts, so within every cell the local order is
// the serial one, and so is every per-cell sum: the owned particles' new states are the serial
// run's to the bit.

#include "solver/communicator.hpp"

#include <dgmpm/discretisation.hpp>
#include <dgmpm/subdomain.hpp>

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <string>
#include <vector>

namespace dgmpm {

template <class ParticleSet>
class Halo {
 public:
  static constexpr int Dim = ParticleSet::dim;
  using Index = std::array<int, Dim>;

  // On `subdomain` (its window's depth: one ghost layer per stage); distribute() gives the
  // particles.
  Halo(Communicator& comm, const Subdomain<Dim>& subdomain) : comm_(comm), sub_(subdomain) {
    owned_cell_.resize(sub_.window().num_cells());
    for (int c = 0; c < sub_.window().num_cells(); ++c)
      owned_cell_[c] = sub_.owns(sub_.full_cell(c));
  }

  const Subdomain<Dim>& subdomain() const { return sub_; }
  Communicator& comm() const { return comm_; }
  int owned() const { return owned_; }
  long global_index(int i) const { return global_[i]; }
  // What the exchanges cost so far (for the scaling benchmark): seconds spent in them (waits for
  // slower partners included), how many, and the bytes this rank sent.
  struct Traffic {
    double seconds = 0;
    long exchanges = 0;
    double bytes_sent = 0;
  };
  const Traffic& traffic() const { return traffic_; }

  // Whether cell c of the window belongs to this rank's block.
  bool owns_cell(int c) const { return owned_cell_[c]; }

  // This rank's particles from all of them (in the serial run's order); sets up the exchanges of
  // fixed particles.
  ParticleSet distribute(const ParticleSet& all) {
    std::vector<int> owned, ghosts;
    std::vector<Index> owned_cells, ghost_cells;
    Index k{};
    for (int p = 0; p < all.size(); ++p) {
      if (!sub_.locate(all.position.col(p), k)) throw_outside_grid(all, p);
      if (sub_.owns(k)) {
        owned.push_back(p);
        owned_cells.push_back(k);
      } else if (sub_.holds(k)) {
        ghosts.push_back(p);
        ghost_cells.push_back(k);
      }
    }
    owned_ = static_cast<int>(owned.size());
    std::vector<int> order = owned;
    order.insert(order.end(), ghosts.begin(), ghosts.end());
    std::vector<Index>& cells = owned_cells;  // of the local particles, in their order
    cells.insert(cells.end(), ghost_cells.begin(), ghost_cells.end());
    global_.assign(order.begin(), order.end());
    ParticleSet local = all.select(order);
    // Fixed particles: what goes to and comes from each partner, in the serial order both sides
    // enumerate.
    const auto& partners = sub_.partners();
    send_.assign(partners.size(), {});
    receive_.assign(partners.size(), {});
    for (int i = 0; i < local.size(); ++i) {
      k = cells[i];
      for (std::size_t j = 0; j < partners.size(); ++j) {
        if (i < owned_ && sub_.partner_holds(static_cast<int>(j), k)) send_[j].push_back(i);
        if (i >= owned_ && sub_.owner(k) == partners[j]) receive_[j].push_back(i);
      }
    }
    return local;
  }

  // After a step of fixed particles: the ghosts take their owners' new states (every field a
  // step changes).
  void exchange_states(ParticleSet& p) {
    const std::size_t n = send_.size();
    const std::size_t width = static_cast<std::size_t>(p.stepped_width());
    out_.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
      out_[j].resize(send_[j].size() * width);
      for (std::size_t e = 0; e < send_[j].size(); ++e)
        p.write_stepped(send_[j][e], out_[j].data() + e * width);
    }
    exchange();
    for (std::size_t j = 0; j < n; ++j) {
      if (in_[j].size() != receive_[j].size() * width)
        throw std::logic_error("halo: rank " + std::to_string(sub_.partners()[j]) + " sent " +
                               std::to_string(in_[j].size()) + " values, expected " +
                               std::to_string(receive_[j].size() * width));
      for (std::size_t e = 0; e < receive_[j].size(); ++e)
        p.read_stepped(receive_[j][e], in_[j].data() + e * width);
    }
  }

  // After a step of moving particles (positions advanced): each owner sends its particles to every
  // partner whose window holds them (migration included: a particle entering a partner's block is
  // in its window), and the local set is rebuilt from the owned particles still in the window and
  // what came in. Throws ParticleOutsideGrid for an owned particle that left the grid.
  void migrate(ParticleSet& p) {
    const int width = 1 + p.record_width();  // the global index, then the fields
    const auto& partners = sub_.partners();
    out_.resize(partners.size());
    for (auto& o : out_) o.clear();  // capacity kept from step to step
    // The owned particles still in the window (those that left the block stay as ghosts: no
    // other rank sends them here), as records too: one way in.
    kept_.clear();
    Index k{};
    for (int i = 0; i < owned_; ++i) {
      if (!sub_.locate(p.position.col(i), k)) throw_outside_grid(p, i);
      const int owner = sub_.owner(k);
      if (sub_.holds(k)) pack(p, i, kept_);
      bool sent_to_owner = owner == sub_.rank();
      for (std::size_t j = 0; j < partners.size(); ++j) {
        if (!sub_.partner_holds(static_cast<int>(j), k)) continue;
        pack(p, i, out_[j]);
        sent_to_owner = sent_to_owner || partners[j] == owner;
      }
      if (!sent_to_owner)
        throw std::runtime_error("particle " + std::to_string(p.id[i]) + " moved by more than " +
                                 "the ghost layers in one step: past the ranks next to rank " +
                                 std::to_string(sub_.rank()));
    }
    exchange();
    // The new local set: every record, owned particles first, each part in global order. Built
    // in the set the previous step left (next_): when the count is unchanged, as on most steps,
    // nothing is allocated.
    owned_entries_.clear();
    ghost_entries_.clear();
    const auto sort_in = [&](const std::vector<double>& buffer) {
      for (std::size_t e = 0; e < buffer.size(); e += width) {
        const double* r = buffer.data() + e;
        Eigen::Map<const Eigen::Matrix<double, Dim, 1>> x(r + 1 + ParticleSet::record_position);
        sub_.locate(x, k);
        (sub_.owns(k) ? owned_entries_ : ghost_entries_).push_back({static_cast<long>(r[0]), r});
      }
    };
    sort_in(kept_);
    for (const auto& buffer : in_) sort_in(buffer);
    const auto by_global = [](const Entry& a, const Entry& b) { return a.global < b.global; };
    std::sort(owned_entries_.begin(), owned_entries_.end(), by_global);
    std::sort(ghost_entries_.begin(), ghost_entries_.end(), by_global);
    const int n = static_cast<int>(owned_entries_.size() + ghost_entries_.size());
    next_.tracks_reference = p.tracks_reference;
    next_.resize(n);
    global_.resize(n);
    owned_ = static_cast<int>(owned_entries_.size());
    for (int i = 0; i < n; ++i) {
      const Entry& e = i < owned_ ? owned_entries_[i] : ghost_entries_[i - owned_];
      global_[i] = e.global;
      next_.read_record(i, e.record + 1);
    }
    std::swap(p, next_);  // Eigen's and std's moves swap buffers: no copy, no allocation
  }

  // A restart: `p` holds this rank's owned particles (in the serial order, `global` their serial
  // indices) from its checkpoint; the ghosts come from their owners.
  void restore(ParticleSet& p, const std::vector<long>& global) {
    owned_ = p.size();
    global_ = global;
    migrate(p);
  }

  // Columns of the owned particles (the first owned() columns of `local`), gathered on rank 0 in
  // the serial run's order; an empty matrix on the other ranks.
  Eigen::MatrixXd gather(const Eigen::MatrixXd& local) const {
    const int rows = static_cast<int>(local.rows());
    std::vector<double> mine;
    mine.reserve(static_cast<std::size_t>(owned_) * (rows + 1));
    for (int i = 0; i < owned_; ++i) {
      mine.push_back(static_cast<double>(global_[i]));
      for (int r = 0; r < rows; ++r) mine.push_back(local(r, i));
    }
    const std::vector<double> all = comm_.gather(mine);
    if (sub_.rank() != 0) return {};
    const long n = static_cast<long>(all.size()) / (rows + 1);
    Eigen::MatrixXd out(rows, n);
    for (long e = 0; e < n; ++e) {
      const long g = static_cast<long>(all[e * (rows + 1)]);
      if (g < 0 || g >= n) throw std::logic_error("halo: gathered particle index out of range");
      for (int r = 0; r < rows; ++r) out(r, g) = all[e * (rows + 1) + 1 + r];
    }
    return out;
  }

 private:
  void exchange() {
    const auto start = std::chrono::steady_clock::now();
    comm_.exchange(sub_.partners(), out_, in_);
    traffic_.seconds +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++traffic_.exchanges;
    for (const auto& o : out_) traffic_.bytes_sent += 8.0 * static_cast<double>(o.size());
  }

  // A moving particle's record: its global index (a double holds it exactly below 2^53), then its
  // fields.
  void pack(const ParticleSet& p, int i, std::vector<double>& out) const {
    out.push_back(static_cast<double>(global_[i]));
    p.write_record(i, out);
  }

  Communicator& comm_;
  Subdomain<Dim> sub_;
  std::vector<char> owned_cell_;
  std::vector<long> global_;  // serial index of each local particle
  int owned_ = 0;
  std::vector<std::vector<int>> send_, receive_;  // fixed particles: local indices per partner
  std::vector<std::vector<double>> out_, in_;
  std::vector<double> kept_;
  // Moving particles: the records of the new local set, and the set the last migration replaced.
  struct Entry {
    long global;
    const double* record;
  };
  std::vector<Entry> owned_entries_, ghost_entries_;
  ParticleSet next_;
  Traffic traffic_;
};

}  // namespace dgmpm
