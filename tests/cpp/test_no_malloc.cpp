// core/no_malloc.hpp: SATGNC_NO_MALLOC_SCOPE forbids Eigen heap allocation inside its scope and
// restores the previous state after it; an allocating Eigen expression inside the scope asserts.
// This file is compiled with EIGEN_RUNTIME_NO_MALLOC and without NDEBUG (tests/cpp/CMakeLists.txt)
// and calls no library function, so the check runs in every build type.
#include <gtest/gtest.h>

#include <Eigen/Core>

#include "satgnc/core/no_malloc.hpp"

namespace core = satgnc::core;

namespace {
// Allocating Eigen expression: a dynamic-size matrix created inside the scope.
double allocate_inside_scope(int n) {
  SATGNC_NO_MALLOC_SCOPE;
  Eigen::MatrixXd m = Eigen::MatrixXd::Constant(n, n, 1.0);
  return m.sum();
}

// Fixed-size work and work on preallocated buffers are allowed inside the scope.
double fixed_size_inside_scope(Eigen::VectorXd& buffer) {
  SATGNC_NO_MALLOC_SCOPE;
  Eigen::Matrix<double, 6, 6> a = Eigen::Matrix<double, 6, 6>::Identity();
  buffer.setConstant(2.0);
  buffer.head<6>() += a.diagonal();
  return buffer.sum();
}
}  // namespace

TEST(NoMalloc, ScopeForbidsAndRestores) {
  static_assert(core::kNoMallocGuard, "this file is compiled with EIGEN_RUNTIME_NO_MALLOC");
  EXPECT_TRUE(core::malloc_allowed());
  {
    SATGNC_NO_MALLOC_SCOPE;
    EXPECT_FALSE(core::malloc_allowed());
    {
      SATGNC_NO_MALLOC_SCOPE;  // nested scopes (ScpSolver -> inner solver) restore the outer state
      EXPECT_FALSE(core::malloc_allowed());
    }
    EXPECT_FALSE(core::malloc_allowed());
  }
  EXPECT_TRUE(core::malloc_allowed());
}

TEST(NoMalloc, AllocationFreeWorkPasses) {
  Eigen::VectorXd buffer(10);  // allocated before the scope
  EXPECT_DOUBLE_EQ(fixed_size_inside_scope(buffer), 26.0);
  EXPECT_TRUE(core::malloc_allowed());
}

TEST(NoMallocDeathTest, AllocationInsideTheScopeAsserts) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(allocate_inside_scope(50), "heap allocation is forbidden");
  EXPECT_DOUBLE_EQ(Eigen::MatrixXd::Constant(50, 50, 1.0).sum(), 2500.0);  // outside: allowed
}
