#pragma once
// The roofline of `dgmpm bench --json`: a step's rate against the two bounds of this machine, the
// arithmetic peak (independent multiply-adds, measured in the same run) and the memory bound
// (triad bandwidth over the bytes a particle-step must move). Flops per particle-step are counted
// from the executed instructions of the steps themselves by bench/count_flops.py (callgrind):
// the machine has no hardware counters to read.

#include <map>
#include <nlohmann/json.hpp>
#include <string>

namespace dgmpm::bench {

// Floating-point operations per second of independent multiply-add chains (one thread):
// `build` as this build compiles them (its instruction set: SSE2's two-wide mul and add unless
// built with -DDGMPM_NATIVE=ON), `fma` with the CPU's 256-bit FMA (AVX2; 0 when it has none):
// the peak the steps could reach if compiled for it.
struct ArithmeticPeak {
  double build = 0, fma = 0;
};
ArithmeticPeak measure_arithmetic_peak(int runs);

// A case's counts per particle-step, from count_flops.py's JSON: floating-point operations and
// instructions executed (of the binary counted).
struct StepCount {
  double flops = 0, instructions = 0;
};
// The counts per case name ({"cases": {name: {"flops_per_particle_step": x,
// "instructions_per_particle_step": y}}}). Throws std::runtime_error naming the file, the key and
// what is wrong.
std::map<std::string, StepCount> read_step_counts(const std::string& path);

// One case's roofline: its achieved flop and instruction rates, the fraction of the peak (the
// triad's fraction is the case's fraction_of_bound), which bound binds (the lower of peak / flops
// and triad / bytes particle-steps per second) and how close the rate is to it.
nlohmann::json roofline(const StepCount& count, double particle_steps_per_second,
                        double bytes_per_particle_step, const ArithmeticPeak& peak,
                        double triad_bytes_per_second);

}  // namespace dgmpm::bench
