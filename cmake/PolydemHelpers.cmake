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

# Precompiled headers (-DPOLYDEM_PCH=ON): Eigen's Core and Geometry (through core/types.h in almost
# every file) and the standard headers most files include are parsed once, into one header that
# every module's library reuses, instead of once per file. A precompiled header is the same text
# compiled ahead, so the object code is the same with or without it. Off by default until a whole
# build with it has been checked against the reference state hashes. ccache caches a compile that
# uses one only when told (CCACHE_SLOPPINESS=pch_defines,time_macros).
set(POLYDEM_PCH_HEADERS <algorithm> <array> <cmath> <cstdint> <functional> <limits> <map> <memory>
                        <optional> <span> <string> <string_view> <utility> <vector> <Eigen/Core>
                        <Eigen/Geometry>)
option(POLYDEM_PCH "Precompiled headers for the modules and the polydem program" OFF)
if(POLYDEM_PCH)
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
