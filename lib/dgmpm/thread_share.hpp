#pragma once
// How the threaded sweeps split their work: each thread of a parallel region takes one contiguous
// share of a range [0, n), in thread order, so that every item has one owner and the shares do
// not depend on anything but n and the team's size.

#ifdef _OPENMP
#include <omp.h>
#endif

namespace dgmpm {

// The calling thread's place in its parallel region (0 of 1 outside one, or without OpenMP).
struct TeamPlace {
  int thread = 0, team = 1;
};
inline TeamPlace team_place() {
#ifdef _OPENMP
  return {omp_get_thread_num(), omp_get_num_threads()};
#else
  return {};
#endif
}

// The share [begin, end) of [0, n) that `place.thread` takes.
struct Share {
  int begin = 0, end = 0;
};
inline Share thread_share(int n, const TeamPlace& place) {
  return {static_cast<int>(static_cast<long>(n) * place.thread / place.team),
          static_cast<int>(static_cast<long>(n) * (place.thread + 1) / place.team)};
}

}  // namespace dgmpm
