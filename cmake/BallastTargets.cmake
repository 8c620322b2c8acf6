# Helpers shared by the module CMakeLists.

# The order CTest starts tests in (highest COST first) when it has no timings of its own, as on
# a fresh CI checkout: the real-time tests first, one after another on a quiet machine (RUN_SERIAL:
# CTest starts one only when nothing else runs), then the simulations of the whole robot (seconds
# to a minute each, so none is left running alone at the end), then the rest.
set(BALLAST_TEST_COST_REAL_TIME 1000)
set(BALLAST_TEST_COST_SIMULATION 50)

# ballast_add_gtest(NAME name SOURCES ... LIBS ... [LABELS ...] [COST c] [REAL_TIME])
# A GoogleTest executable in build/bin whose tests CTest discovers one by one.
# REAL_TIME: the tests measure wall-clock timing; they run alone (RUN_SERIAL) and carry the
# label realtime (instead of LABELS), so the rest of the suite cannot starve them.
# COST: CTest's cost of each test (see BALLAST_TEST_COST_*).
function(ballast_add_gtest)
  cmake_parse_arguments(T "REAL_TIME" "NAME;COST" "SOURCES;LIBS;LABELS" ${ARGN})
  add_executable(${T_NAME} ${T_SOURCES})
  target_link_libraries(${T_NAME} PRIVATE ${T_LIBS} GTest::gtest_main)
  target_include_directories(${T_NAME} PRIVATE ${PROJECT_SOURCE_DIR})
  # The tests' own code is checks and set-up; the code they run is the libraries', optimised.
  # At -O1 their gtest and Eigen expansions, most of a cold build, compile a quarter faster.
  target_compile_options(${T_NAME} PRIVATE $<$<CONFIG:Release>:-O1>)
  target_compile_definitions(${T_NAME} PRIVATE
    BALLAST_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    BALLAST_TEST_DATA_DIR="${PROJECT_SOURCE_DIR}/test/data")
  if(NOT T_COST)
    set(T_COST 0)  # CTest's own default
  endif()
  if(T_REAL_TIME)
    # One label: gtest_discover_tests flattens its PROPERTIES, a list of labels would not survive.
    gtest_discover_tests(${T_NAME} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS realtime RUN_SERIAL TRUE
                         COST ${BALLAST_TEST_COST_REAL_TIME})
  else()
    gtest_discover_tests(${T_NAME} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "${T_LABELS}"
                         COST ${T_COST})
  endif()
endfunction()

# Backend plugins: build/lib/ballast/libballast_backend_<name>.so, installed to <libdir>/ballast.
set(BALLAST_PLUGIN_BUILD_DIR ${PROJECT_BINARY_DIR}/lib/ballast)

# ballast_add_backend(NAME name SOURCES ...): a plugin module that sees only the ABI header.
function(ballast_add_backend)
  cmake_parse_arguments(B "" "NAME" "SOURCES" ${ARGN})
  set(target ballast_backend_${B_NAME})
  add_library(${target} MODULE ${B_SOURCES})
  set_target_properties(${target} PROPERTIES
    LIBRARY_OUTPUT_DIRECTORY ${BALLAST_PLUGIN_BUILD_DIR}
    CXX_VISIBILITY_PRESET hidden VISIBILITY_INLINES_HIDDEN ON)
  target_link_libraries(${target} PRIVATE ballast_backend_abi)
  install(TARGETS ${target} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}/ballast)
endfunction()
