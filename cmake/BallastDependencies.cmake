# Every external package, found once. All are Debian bookworm packages (see .ci/bootstrap).
find_package(Eigen3 3.4 REQUIRED NO_MODULE)
find_package(urdfdom REQUIRED)
# Only ceres/jet.h (forward-mode AD) is used: header-only, so the static Ceres archive and its
# glog/gflags/SuiteSparse dependencies are not linked.
find_path(CERES_JET_INCLUDE_DIR ceres/jet.h REQUIRED)
if(BALLAST_WITH_SIMBODY)
  find_package(Simbody 3.7 REQUIRED CONFIG)
endif()
if(BALLAST_BUILD_TESTS)
  find_package(GTest REQUIRED)
endif()
if(BALLAST_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)
endif()
