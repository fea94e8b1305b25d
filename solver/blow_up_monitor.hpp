#pragma once
// The run's guard against unbounded growth: the energy cannot exceed the initial energy plus the
// work the loads did (DGMPM dissipates; MPM's balance is looser, hence a wide factor). Checked
// every kInterval steps: energy is a pass over the particles, and that is often enough to stop an
// exponential growth long before it overflows.

#include "solver/checkpoint.hpp"

#include <algorithm>
#include <cstdint>
#include <nlohmann/json.hpp>

namespace dgmpm {

class BlowUpMonitor {
 public:
  static constexpr int kInterval = 16;

  BlowUpMonitor(bool enabled, double factor) : enabled_(enabled), factor_(factor) {}
  void start(double initial_energy) { initial_energy_ = initial_energy; }
  double initial_energy() const { return initial_energy_; }
  double factor() const { return factor_; }
  // Counts a step; true when the energy is to be checked now.
  bool due() { return enabled_ && ++since_check_ >= kInterval; }
  // The reference (initial energy plus the most work done so far, `work` the loads' work now)
  // the energy e is measured against; e exceeds it when above factor() times it.
  double reference(double work) {
    since_check_ = 0;
    most_work_ = std::max(most_work_, work);
    return initial_energy_ + most_work_;
  }
  bool exceeds(double e, double reference) const { return e > factor_ * reference && e > 0.0; }

  void save(nlohmann::json& header) const {
    header["most_work"] = checkpoint::bits(most_work_);
    header["initial_energy"] = checkpoint::bits(initial_energy_);
    header["since_growth_check"] = since_check_;
  }
  void restore(const nlohmann::json& h) {
    most_work_ = checkpoint::from_bits(h.at("most_work").get<std::uint64_t>());
    initial_energy_ = checkpoint::from_bits(h.at("initial_energy").get<std::uint64_t>());
    since_check_ = h.at("since_growth_check").get<int>();
  }

 private:
  bool enabled_;
  double factor_;
  double initial_energy_ = 0, most_work_ = 0;
  int since_check_ = 0;
};

}  // namespace dgmpm
