# Helpers shared by all modules, apps and tests.
#
#   polydem_add_module(NAME core SOURCES a.cpp b.cpp DEPENDS Eigen3::Eigen ...)
#     -> static library polydem_core, alias polydem::core, headers included as
#        "polydem/core/a.h" (the build's include/polydem is a link to module/, the install puts
#        them under include/polydem/core). Without SOURCES the module is header-only (an
#        INTERFACE library). DEPENDS names every module whose headers it includes
#        (tests/layout checks it against the includes).
#
#   polydem_add_test(NAME geometry_convex_polyhedron SOURCES t.cpp DEPENDS polydem::geometry
#                    [PROCESSES 1 2 4] [LABELS unit] [TIMEOUT 120])
#     -> one GoogleTest executable, registered with ctest once per process count. Counts above 1
#        run through mpiexec with --oversubscribe, and as root where the machine needs it.

# The include root of the build tree: include/polydem -> module/, so that sources and an installed
# tree both include "polydem/<module>/<file>.h".
set(POLYDEM_BUILD_INCLUDE_DIR ${PROJECT_BINARY_DIR}/include CACHE INTERNAL "")
file(MAKE_DIRECTORY ${POLYDEM_BUILD_INCLUDE_DIR})
if(NOT EXISTS ${POLYDEM_BUILD_INCLUDE_DIR}/polydem)
  file(CREATE_LINK ${PROJECT_SOURCE_DIR}/module ${POLYDEM_BUILD_INCLUDE_DIR}/polydem SYMBOLIC)
endif()
set_property(GLOBAL PROPERTY POLYDEM_MODULES "")

# Precompiled headers (POLYDEM_PCH, on by default): Eigen's Core and Geometry (through core/types.h
# in almost every file) and the standard headers most files include are parsed once, into one
# header that every module's library reuses, instead of once per file; the tests share a second one
# (with GoogleTest), the polydem program has its own. A precompiled header is the same text compiled
# ahead, so the object code is the same with or without it (docs/DEVELOPING.md, "Build time").
set(POLYDEM_PCH_HEADERS <algorithm> <array> <cmath> <cstdint> <functional> <limits> <map> <memory>
                        <optional> <span> <sstream> <string> <string_view> <utility> <vector>
                        <Eigen/Core> <Eigen/Geometry>)
option(POLYDEM_PCH "Precompiled headers for the modules, the polydem program and the tests" ON)
if(POLYDEM_PCH)
  # ccache caches a compile that includes a precompiled header only with this sloppiness (ccache's
  # manual, "Precompiled headers"): a ccache launcher gets it, so that cached builds stay cached.
  foreach(lang C CXX)
    if(CMAKE_${lang}_COMPILER_LAUNCHER MATCHES "ccache$")
      set(CMAKE_${lang}_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env
                                          CCACHE_SLOPPINESS=pch_defines,time_macros
                                          ${CMAKE_${lang}_COMPILER_LAUNCHER})
    endif()
  endforeach()
  # The header the modules reuse, compiled with a module's flags (position-independent code).
  # (file(CONFIGURE) rewrites it only when its text changes: a reconfigure rebuilds nothing.)
  file(CONFIGURE OUTPUT ${PROJECT_BINARY_DIR}/polydem_pch.cpp
       CONTENT "// Compiles the modules' precompiled header.\n")
  add_library(polydem_pch STATIC ${PROJECT_BINARY_DIR}/polydem_pch.cpp)
  target_link_libraries(polydem_pch PRIVATE Eigen3::Eigen)
  set_target_properties(polydem_pch PROPERTIES POSITION_INDEPENDENT_CODE ON)
  target_precompile_headers(polydem_pch PRIVATE ${POLYDEM_PCH_HEADERS})
endif()

# Lets `target` compile with the precompiled header: a module library reuses the modules' one
# (same flags), another target (an executable) gets its own.
function(polydem_use_pch target)
  if(NOT POLYDEM_PCH)
    return()
  endif()
  get_target_property(pic ${target} POSITION_INDEPENDENT_CODE)
  if(pic)
    target_precompile_headers(${target} REUSE_FROM polydem_pch)
  else()
    target_precompile_headers(${target} PRIVATE ${POLYDEM_PCH_HEADERS})
  endif()
endfunction()

# Unity builds (POLYDEM_UNITY, on by default): a module library or program compiles its files
# POLYDEM_UNITY_BATCH at a time, each batch as one file that includes them, so that the headers
# they share are parsed and their inline functions compiled once per batch instead of once per
# file. The code is the same; only what the compiler sees at once is larger. Every file of a
# target may land in a batch with any other, so a file-local name (anonymous namespace, static)
# must not repeat one of another file of its target: a repeat fails the build with
# "redefinition of ..." in a unity_*.cxx; give the helper a name of its own or share it through a
# header (docs/DEVELOPING.md, "Build time").
option(POLYDEM_UNITY "Compile each module's files in batches (unity build)" ON)
set(POLYDEM_UNITY_BATCH 8 CACHE STRING "Files per batch of a unity build (0: one batch a target)")

function(polydem_use_unity target)
  if(POLYDEM_UNITY)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_MODE BATCH
                                               UNITY_BUILD_BATCH_SIZE ${POLYDEM_UNITY_BATCH})
  endif()
endfunction()

function(polydem_add_module)
  cmake_parse_arguments(M "" "NAME" "SOURCES;DEPENDS" ${ARGN})
  set(target polydem_${M_NAME})
  if(M_SOURCES)
    add_library(${target} STATIC ${M_SOURCES})
    target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${POLYDEM_BUILD_INCLUDE_DIR}>
                                                $<INSTALL_INTERFACE:include>)
    target_link_libraries(${target} PUBLIC ${M_DEPENDS})
    set_target_properties(${target} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    polydem_use_pch(${target})
    polydem_use_unity(${target})
  else()
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE $<BUILD_INTERFACE:${POLYDEM_BUILD_INCLUDE_DIR}>
                                                   $<INSTALL_INTERFACE:include>)
    target_link_libraries(${target} INTERFACE ${M_DEPENDS})
  endif()
  add_library(polydem::${M_NAME} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${M_NAME})
  set_property(GLOBAL APPEND PROPERTY POLYDEM_MODULES ${M_NAME})
endfunction()

# Environment for every MPI launch made by ctest: lets Open MPI run as root (CI containers do),
# allows more ranks than cores, and avoids the ptrace-based single-copy transport that
# containers forbid.
set(POLYDEM_MPI_TEST_ENV
    "OMPI_ALLOW_RUN_AS_ROOT=1;OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1;OMPI_MCA_rmaps_base_oversubscribe=1;OMPI_MCA_btl_vader_single_copy_mechanism=none"
    CACHE INTERNAL "")

function(polydem_add_test)
  cmake_parse_arguments(T "" "NAME;TIMEOUT" "SOURCES;DEPENDS;PROCESSES;LABELS;ARGS" ${ARGN})
  if(NOT T_PROCESSES)
    set(T_PROCESSES 1)
  endif()
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 300)
  endif()
  set(exe test_${T_NAME})
  add_executable(${exe} ${T_SOURCES})
  target_link_libraries(${exe} PRIVATE ${T_DEPENDS} polydem_test_main GTest::gtest)
  if(POLYDEM_PCH)
    # The tests' precompiled header (tests/CMakeLists.txt): same flags as every test executable.
    target_precompile_headers(${exe} REUSE_FROM polydem_test_main)
  endif()
  set_target_properties(${exe} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/tests)
  foreach(np IN LISTS T_PROCESSES)
    if(np EQUAL 1)
      add_test(NAME ${T_NAME} COMMAND ${exe} ${T_ARGS})
    else()
      add_test(NAME ${T_NAME}_np${np}
               COMMAND ${MPIEXEC_EXECUTABLE} ${MPIEXEC_NUMPROC_FLAG} ${np} --oversubscribe
                       $<TARGET_FILE:${exe}> ${T_ARGS})
    endif()
    set(name ${T_NAME})
    if(NOT np EQUAL 1)
      set(name ${T_NAME}_np${np})
    endif()
    set_tests_properties(${name} PROPERTIES ENVIRONMENT "${POLYDEM_MPI_TEST_ENV}"
                                            TIMEOUT ${T_TIMEOUT} PROCESSORS ${np}
                                            LABELS "${T_LABELS}")
  endforeach()
endfunction()
