# Every external package, found once, here. All are Debian bookworm packages (.ci/bootstrap
# installs them); nothing is downloaded at build time.
set(THREADS_PREFER_PTHREAD_FLAG ON)
find_package(Threads REQUIRED)
find_package(Eigen3 3.4 REQUIRED NO_MODULE)            # Eigen3::Eigen
find_package(urdfdom REQUIRED)                         # urdfdom::urdfdom_model
find_package(yaml-cpp 0.7 REQUIRED)                    # yaml-cpp
find_package(octomap REQUIRED)                         # octomap, octomath
find_package(spdlog 1.10 REQUIRED)                     # spdlog::spdlog
find_package(CLI11 2.1 REQUIRED)                       # CLI11::CLI11
find_package(nlohmann_json 3.11 REQUIRED)              # nlohmann_json::nlohmann_json
find_package(PkgConfig REQUIRED)
pkg_check_modules(zstd REQUIRED IMPORTED_TARGET libzstd)  # PkgConfig::zstd (libzstd-dev): .blog
# Only ceres/jet.h (forward-mode AD) is used: header-only, so the static Ceres archive and its
# glog/gflags/SuiteSparse dependencies are not linked.
find_path(CERES_JET_INCLUDE_DIR ceres/jet.h REQUIRED)
find_program(GNUPLOT_EXECUTABLE gnuplot)               # `ballast plot`; optional at build time
if(BALLAST_WITH_SIMBODY)
  find_package(Simbody 3.7 REQUIRED CONFIG)            # ${Simbody_LIBRARIES}; users need -UNDEBUG
endif()
if(BALLAST_WITH_MUJOCO)
  find_package(mujoco 2.2 REQUIRED CONFIG)             # mujoco::mujoco (2.2.2 on bookworm)
  # Debian's mujocoTargets.cmake names /usr/include/libqhull_r/ (libqhull-dev, which nothing
  # here needs) among the target's include directories, and CMake refuses a missing one.
  get_target_property(_mujoco_includes mujoco::mujoco INTERFACE_INCLUDE_DIRECTORIES)
  set(_mujoco_existing)
  foreach(dir IN LISTS _mujoco_includes)
    if(EXISTS "${dir}")
      list(APPEND _mujoco_existing "${dir}")
    endif()
  endforeach()
  set_target_properties(mujoco::mujoco PROPERTIES INTERFACE_INCLUDE_DIRECTORIES "${_mujoco_existing}")
endif()
if(BALLAST_BUILD_TESTS)
  find_package(GTest REQUIRED)                         # GTest::gtest_main
endif()
if(BALLAST_BUILD_BENCHMARKS)
  find_package(benchmark REQUIRED)                     # benchmark::benchmark_main
endif()
