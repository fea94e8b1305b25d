#include "bench/courant_bench.hpp"

#include "stability/admissible_courant.hpp"
#include "stability/courant_map.hpp"

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <ostream>
#include <vector>

namespace dgmpm::bench {
namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

void run_courant_benchmark(std::ostream& out) {
  using namespace dgmpm::stability;
  const std::vector<CellLayout> layouts{regular_layout(1),
                                        regular_layout(2),
                                        regular_layout(3),
                                        regular_layout(4),
                                        CellLayout{{0.6083, 0.955}, {}},
                                        CellLayout{{0.05, 0.3, 0.55, 0.9}, {1, 2, 1, 1.5}}};
  out << "courant query (elastic model, map built from lib's step + search), median of 31 runs\n";
  out << std::fixed << std::setprecision(3);
  double worst = 0.0;
  for (Criterion criterion : {Criterion::l2, Criterion::monotone})
    for (TimeScheme scheme : {TimeScheme::euler, TimeScheme::rk2})
      for (const auto& layout : layouts) {
        std::vector<double> times;
        double courant = 0.0;
        for (int run = 0; run < 31; ++run) {
          const auto start = Clock::now();
          courant = admissible_courant(layout, scheme, criterion, Model::elastic).courant;
          times.push_back(seconds_since(start));
        }
        const double m = median(times) * 1e3;
        worst = std::max(worst, m);
        out << "  " << std::setw(8) << to_string(criterion) << ' ' << std::setw(5)
            << to_string(scheme) << "  N = " << layout.size() << "  positions "
            << describe(layout.positions) << ": C* = " << std::setprecision(6) << courant
            << std::setprecision(3) << ", " << m << " ms\n";
      }
  out << "  slowest median: " << worst << " ms (goal < 1 ms)\n";

  out << "two-particle map 100 x 100 (dgmpm courant --map 100, elastic, one core)\n";
  for (Criterion criterion : {Criterion::l2, Criterion::monotone}) {
    const auto start = Clock::now();
    const auto map =
        two_particle_courant_map(100, {}, TimeScheme::euler, criterion, Model::elastic);
    out << "  " << to_string(criterion) << " euler: " << seconds_since(start)
        << " s (goal < 10 s)\n";
  }
}

void run_courant_2d_benchmark(std::ostream& out, int repeats) {
  using namespace dgmpm::stability;
  const std::vector<CellLayout> layouts{regular_layout(1, 2),
                                        CellLayout{{0.25, 0.5, 0.75, 0.5}, {}, 2},
                                        regular_layout(2, 2), regular_layout(3, 2)};
  out << "2D courant query (map built from lib's 2D step + search), min and median of " << repeats
      << " runs\n";
  out << std::fixed << std::setprecision(3);
  for (Model model : {Model::advection, Model::elastic})
    for (Criterion criterion : {Criterion::l2, Criterion::monotone}) {
      if (model == Model::elastic && criterion == Criterion::monotone) continue;  // refused
      for (TimeScheme scheme : {TimeScheme::euler, TimeScheme::rk2})
        for (FluxScheme flux : {FluxScheme::dcu, FluxScheme::ctu})
          for (const auto& layout : layouts) {
            AnalysisSetting s;
            s.dim = 2;
            s.model = model;
            s.time = scheme;
            s.flux = flux;
            s.speed_y = 1.0;
            std::vector<double> times;
            double courant = 0.0;
            for (int run = 0; run < repeats; ++run) {
              const auto start = Clock::now();
              courant = admissible_courant(layout, s, criterion).courant;
              times.push_back(seconds_since(start));
            }
            out << "  " << std::setw(9) << to_string(model) << ' ' << std::setw(8)
                << to_string(criterion) << ' ' << std::setw(5) << to_string(scheme) << ' '
                << to_string(flux) << "  N = " << layout.size() << ": C* = " << std::setprecision(4)
                << courant << std::setprecision(1) << ", min "
                << *std::min_element(times.begin(), times.end()) * 1e3 << " ms, median "
                << median(times) * 1e3 << " ms\n"
                << std::setprecision(3);
          }
    }
  out << "  (goal: under 50 ms for 4 particles, elastic, RK2, L2)\n";
}

}  // namespace dgmpm::bench
