#include "bench/roofline.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <fstream>
#include <stdexcept>

namespace dgmpm::bench {

namespace {

// Independent chains x = x a + b: enough of them to cover the latency of both pipes (mul then
// add: 6 cycles, 2 per cycle, two doubles per SSE2 register; FMA: 4 cycles, 2 per cycle, four
// doubles per AVX2 register).
constexpr int kChains = 48;
constexpr long kIterations = 1L << 22;
constexpr double kA = 0.999999, kB = 1e-6;  // x stays near 1: no denormal, no overflow

[[gnu::noinline]] double multiply_adds(long iterations, double a, double b) {
  std::array<double, kChains> x{};
  for (int k = 0; k < kChains; ++k) x[k] = 1.0 + 1e-3 * k;
  for (long i = 0; i < iterations; ++i)
    for (int k = 0; k < kChains; ++k) x[k] = x[k] * a + b;
  double sum = 0;
  for (double v : x) sum += v;
  return sum;
}

#if defined(__x86_64__) && defined(__GNUC__)
#define DGMPM_BENCH_FMA 1
[[gnu::noinline, gnu::target("avx2,fma")]] double fused_multiply_adds(long iterations, double a,
                                                                      double b) {
  std::array<double, kChains> x{};
  for (int k = 0; k < kChains; ++k) x[k] = 1.0 + 1e-3 * k;
  for (long i = 0; i < iterations; ++i)
    for (int k = 0; k < kChains; ++k) x[k] = std::fma(x[k], a, b);
  double sum = 0;
  for (double v : x) sum += v;
  return sum;
}
#endif

// Flops per second of `kernel`, best of `runs` (2 flops per multiply-add).
template <class Kernel>
double best_flops_per_second(int runs, Kernel kernel) {
  double best = 0, sink = 0;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    sink += kernel(kIterations, kA, kB + 1e-9 * r);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    best = std::max(best, 2.0 * kChains * static_cast<double>(kIterations) / s);
  }
  if (!std::isfinite(sink)) throw std::logic_error("bench: the peak kernel lost its values");
  return best;
}

}  // namespace

ArithmeticPeak measure_arithmetic_peak(int runs) {
  ArithmeticPeak peak;
  peak.build = best_flops_per_second(runs, multiply_adds);
#ifdef DGMPM_BENCH_FMA
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))
    peak.fma = best_flops_per_second(runs, fused_multiply_adds);
#endif
  return peak;
}

std::map<std::string, StepCount> read_step_counts(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("--flop-counts: cannot read \"" + path + "\"");
  nlohmann::json doc;
  try {
    in >> doc;
  } catch (const nlohmann::json::exception& e) {
    throw std::runtime_error("--flop-counts: \"" + path + "\" is not JSON: " + e.what());
  }
  if (!doc.contains("cases") || !doc["cases"].is_object())
    throw std::runtime_error("--flop-counts: \"" + path +
                             "\": no object \"cases\" (bench/count_flops.py writes one)");
  std::map<std::string, StepCount> counts;
  for (const auto& [name, entry] : doc["cases"].items()) {
    const auto positive = [&](const char* key) {
      const auto value = entry.find(key);
      if (value == entry.end() || !value->is_number() || !(value->get<double>() > 0))
        throw std::runtime_error("--flop-counts: \"" + path + "\": cases.\"" + name + "\"." + key +
                                 ": a positive number is needed");
      return value->get<double>();
    };
    counts[name] = {positive("flops_per_particle_step"),
                    positive("instructions_per_particle_step")};
  }
  return counts;
}

nlohmann::json roofline(const StepCount& count, double particle_steps_per_second,
                        double bytes_per_particle_step, const ArithmeticPeak& peak,
                        double triad_bytes_per_second) {
  const double achieved = count.flops * particle_steps_per_second;
  const double arithmetic_bound = peak.build / count.flops;
  const double memory_bound = triad_bytes_per_second / bytes_per_particle_step;
  const bool arithmetic = arithmetic_bound <= memory_bound;
  nlohmann::json j = {{"flops_per_particle_step", count.flops},
                      {"flops_per_second", achieved},
                      {"instructions_per_particle_step", count.instructions},
                      {"instructions_per_second", count.instructions * particle_steps_per_second},
                      {"arithmetic_intensity", count.flops / bytes_per_particle_step},
                      {"fraction_of_peak", achieved / peak.build},
                      {"binding_bound", arithmetic ? "arithmetic" : "memory"},
                      {"fraction_of_binding_bound",
                       particle_steps_per_second / std::min(arithmetic_bound, memory_bound)}};
  if (peak.fma > 0) j["fraction_of_fma_peak"] = achieved / peak.fma;
  return j;
}

}  // namespace dgmpm::bench
