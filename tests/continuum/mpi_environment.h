#pragma once
// MPI (and PETSc) for a GoogleTest executable whose main() comes from gtest_main: a global
// test environment that starts them before the first test and stops them after the last.
#include <memory>

#include <gtest/gtest.h>

#include <deal.II/base/mpi.h>

namespace pilelab::testing {

class MpiEnvironment : public ::testing::Environment {
 public:
  void SetUp() override {
    static int argc = 1;
    static char name[] = "continuum_test";
    static char* args[] = {name, nullptr};
    static char** argv = args;
    mpi_ = std::make_unique<dealii::Utilities::MPI::MPI_InitFinalize>(argc, argv, 1);
  }
  void TearDown() override { mpi_.reset(); }

 private:
  std::unique_ptr<dealii::Utilities::MPI::MPI_InitFinalize> mpi_;
};

// Registered once per test executable (this header is included by one .cpp each).
inline ::testing::Environment* const mpi_environment = ::testing::AddGlobalTestEnvironment(new MpiEnvironment);

}  // namespace pilelab::testing
