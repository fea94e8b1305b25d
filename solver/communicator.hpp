#pragma once
// What a distributed run asks of its ranks. The solver does not depend on MPI: an MPI build
// implements this (distributed/mpi_communicator.hpp) and the `dgmpm` binary hands it to the run.
// Every call is collective but exchange() (between partners) and abort(): all ranks make them in
// the same order. Called a few times per step, never inside the per-cell loops.

#include <span>
#include <stdexcept>
#include <vector>

namespace dgmpm {

class Communicator {
 public:
  virtual ~Communicator() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  // Lays the ranks out over the axes of a grid of `cells` (periodic where it is): the number of
  // ranks along each axis (rank_layout, lib/dgmpm/decomposition.hpp), the first axis varying
  // slowest in the rank numbers.
  virtual std::vector<int> cartesian_layout(const std::vector<bool>& periodic,
                                            const std::vector<int>& cells) = 0;
  // Sends send[j] to partners[j] and receives recv[j] from it (sizes need not be known ahead).
  // partners: distinct ranks, each rank listing the other when it is listed.
  virtual void exchange(const std::vector<int>& partners,
                        const std::vector<std::vector<double>>& send,
                        std::vector<std::vector<double>>& recv) = 0;
  virtual void sum(std::span<double> values) = 0;  // in place, over the ranks
  virtual double min(double value) = 0;
  // Rank 0 gets every rank's values, concatenated in rank order; the others an empty vector.
  virtual std::vector<double> gather(const std::vector<double>& values) = 0;
  virtual void barrier() = 0;
  // Ends every rank of the run with `code` (an error on one rank while the others wait).
  [[noreturn]] virtual void abort(int code) = 0;
};

// Thrown by the ranks of a distributed run that stop for an error another rank reports (with
// the details only it has).
struct RankStopped : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// The ranks the binary was launched on: set by an MPI build started by mpirun (main), read by
// the subcommands that distribute (`run`, `bench --what scaling`); nullptr otherwise.
Communicator* launched_ranks();
void set_launched_ranks(Communicator* ranks);

}  // namespace dgmpm
