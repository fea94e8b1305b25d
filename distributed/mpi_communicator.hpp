#pragma once
// The solver's Communicator (solver/communicator.hpp) on MPI: point-to-point exchanges with
// MPI_Isend and a probed MPI_Recv (sizes change when particles move), reductions with
// MPI_Allreduce, gathers with MPI_Gatherv. After cartesian_layout(), calls go through the
// Cartesian communicator (same rank numbers).

#include "cartesian_ranks.hpp"

#include <solver/communicator.hpp>

#include <mpi.h>

#include <stdexcept>
#include <vector>

namespace dgmpm::distributed {

class MpiCommunicator final : public Communicator {
 public:
  explicit MpiCommunicator(MPI_Comm world) : world_(world), comm_(world) {
    MPI_Comm_rank(world_, &rank_);
    MPI_Comm_size(world_, &size_);
  }
  ~MpiCommunicator() override { release(); }
  MpiCommunicator(const MpiCommunicator&) = delete;
  MpiCommunicator& operator=(const MpiCommunicator&) = delete;

  int rank() const override { return rank_; }
  int size() const override { return size_; }

  std::vector<int> cartesian_layout(const std::vector<bool>& periodic,
                                    const std::vector<int>& cells) override {
    release();
    std::vector<int> dims;
    cartesian_ = cartesian_communicator(world_, periodic, dims, cells);
    comm_ = cartesian_;
    return dims;
  }

  void exchange(const std::vector<int>& partners, const std::vector<std::vector<double>>& send,
                std::vector<std::vector<double>>& recv) override {
    const int n = static_cast<int>(partners.size());
    requests_.resize(n);
    for (int j = 0; j < n; ++j)
      MPI_Isend(send[j].data(), static_cast<int>(send[j].size()), MPI_DOUBLE, partners[j], kTag,
                comm_, &requests_[j]);
    recv.resize(n);
    for (int j = 0; j < n; ++j) {
      MPI_Status status;
      MPI_Probe(partners[j], kTag, comm_, &status);
      int count = 0;
      MPI_Get_count(&status, MPI_DOUBLE, &count);
      recv[j].resize(count);
      MPI_Recv(recv[j].data(), count, MPI_DOUBLE, partners[j], kTag, comm_, MPI_STATUS_IGNORE);
    }
    MPI_Waitall(n, requests_.data(), MPI_STATUSES_IGNORE);
  }

  void sum(std::span<double> values) override {
    MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_SUM,
                  comm_);
  }
  double min(double value) override {
    MPI_Allreduce(MPI_IN_PLACE, &value, 1, MPI_DOUBLE, MPI_MIN, comm_);
    return value;
  }

  std::vector<double> gather(const std::vector<double>& values) override {
    int count = static_cast<int>(values.size());
    std::vector<int> counts(rank_ == 0 ? size_ : 0), offsets(counts.size());
    MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, comm_);
    long total = 0;
    for (std::size_t r = 0; r < counts.size(); ++r) {
      offsets[r] = static_cast<int>(total);
      total += counts[r];
    }
    if (total > 2147483647L) throw std::runtime_error("gather: more than 2^31 values on rank 0");
    std::vector<double> all(static_cast<std::size_t>(total));
    MPI_Gatherv(values.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(),
                MPI_DOUBLE, 0, comm_);
    return all;
  }

  void barrier() override { MPI_Barrier(comm_); }
  [[noreturn]] void abort(int code) override {
    MPI_Abort(world_, code);
    throw std::runtime_error("MPI_Abort returned");  // MPI_Abort does not
  }

 private:
  void release() {
    if (cartesian_ != MPI_COMM_NULL) MPI_Comm_free(&cartesian_);
    comm_ = world_;
  }
  static constexpr int kTag = 7;
  MPI_Comm world_, comm_;
  MPI_Comm cartesian_ = MPI_COMM_NULL;
  int rank_ = 0, size_ = 1;
  std::vector<MPI_Request> requests_;
};

}  // namespace dgmpm::distributed
