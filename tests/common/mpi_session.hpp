#pragma once
// MPI around a whole Boost.Test module (tests run under mpirun): include in one file per module.

#include <boost/test/unit_test.hpp>
#include <mpi.h>

namespace dgmpm::test {

struct MpiSession {
  MpiSession() { MPI_Init(nullptr, nullptr); }
  ~MpiSession() { MPI_Finalize(); }
};
BOOST_TEST_GLOBAL_FIXTURE(MpiSession);

}  // namespace dgmpm::test
