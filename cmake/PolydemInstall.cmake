# `cmake --install`: the module libraries and their headers (include/polydem/<module>/), the
# polydem program, and a package configuration so that another project writes
#   find_package(polydem REQUIRED)
#   target_link_libraries(app PRIVATE polydem::polydem)   # or polydem::sim, polydem::run, ...
# (examples/force_operator does; scripts/install-and-example builds it against an install).
include(CMakePackageConfigHelpers)

# The umbrella target polydem::polydem: every module (the executable already owns the name
# `polydem` in this build, hence the target's own name).
get_property(polydem_modules GLOBAL PROPERTY POLYDEM_MODULES)
add_library(polydem_all INTERFACE)
set_target_properties(polydem_all PROPERTIES EXPORT_NAME polydem)
foreach(module IN LISTS polydem_modules)
  target_link_libraries(polydem_all INTERFACE polydem_${module})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/module/${module}/
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/polydem/${module}
          FILES_MATCHING PATTERN "*.h" PATTERN "*.inc")
endforeach()
list(TRANSFORM polydem_modules PREPEND polydem_ OUTPUT_VARIABLE polydem_module_targets)
install(TARGETS ${polydem_module_targets} polydem_all EXPORT polydemTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS polydem RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# The parallel HDF5 the libraries were built with, as the config file recreates it: FindHDF5
# try-compiles a C file, which a C++-only consumer cannot do, so the consumer is handed the
# include directories and libraries this build found instead of searching again.
get_target_property(POLYDEM_HDF5_INCLUDE_DIRS HDF5::HDF5 INTERFACE_INCLUDE_DIRECTORIES)
get_target_property(POLYDEM_HDF5_LIBRARIES HDF5::HDF5 INTERFACE_LINK_LIBRARIES)
get_target_property(POLYDEM_HDF5_DEFINITIONS HDF5::HDF5 INTERFACE_COMPILE_DEFINITIONS)
foreach(var POLYDEM_HDF5_INCLUDE_DIRS POLYDEM_HDF5_LIBRARIES POLYDEM_HDF5_DEFINITIONS)
  if(NOT ${var})
    set(${var} "")
  endif()
endforeach()

set(polydem_cmake_dir ${CMAKE_INSTALL_LIBDIR}/cmake/polydem)
install(EXPORT polydemTargets NAMESPACE polydem:: DESTINATION ${polydem_cmake_dir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/polydemConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/polydemConfig.cmake
                              INSTALL_DESTINATION ${polydem_cmake_dir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/polydemConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/polydemConfig.cmake
              ${PROJECT_BINARY_DIR}/polydemConfigVersion.cmake
              ${PROJECT_SOURCE_DIR}/cmake/FindMETIS.cmake
        DESTINATION ${polydem_cmake_dir})
