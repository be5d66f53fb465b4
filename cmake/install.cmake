# climbsim as a CMake package (issue 14):
#   cmake --install build --prefix P
# puts the public headers in P/include/climbsim/<module>/, the libraries in P/lib/, the
# bundled models in P/share/climbsim/mjcf/ and climbsimConfig.cmake (+ version, targets) in
# P/lib/cmake/climbsim/, so that another project does
#   find_package(climbsim REQUIRED)
#   target_link_libraries(app PRIVATE climbsim::sim)
# The libraries are static (their dependencies are found again by the config file).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(CLIMBSIM_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/climbsim)
set(CLIMBSIM_INSTALL_INCLUDEDIR ${CMAKE_INSTALL_INCLUDEDIR}/climbsim)
set(CLIMBSIM_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/climbsim)

set(climbsim_installed_modules)
foreach(module keys cpg reflex common adhesion scenario robot transition sim inspect optimise
               experiments)
  if(NOT TARGET climbsim_${module})
    continue()
  endif()
  list(APPEND climbsim_installed_modules ${module})
  # Headers are included as "sim/simulation.h": the repository root in the build tree, the
  # include/climbsim folder once installed.
  set_property(TARGET climbsim_${module} PROPERTY INTERFACE_INCLUDE_DIRECTORIES
               $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}>
               $<INSTALL_INTERFACE:${CLIMBSIM_INSTALL_INCLUDEDIR}>)
  set_property(TARGET climbsim_${module} PROPERTY EXPORT_NAME ${module})
  set_property(TARGET climbsim_${module} PROPERTY POSITION_INDEPENDENT_CODE ON)
  install(TARGETS climbsim_${module} EXPORT climbsimTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
          COMPONENT dev)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${module}/
          DESTINATION ${CLIMBSIM_INSTALL_INCLUDEDIR}/${module}
          COMPONENT dev
          FILES_MATCHING PATTERN "*.h")
endforeach()

install(DIRECTORY ${PROJECT_SOURCE_DIR}/mjcf/ DESTINATION ${CLIMBSIM_INSTALL_DATADIR}/mjcf
        COMPONENT dev)
if(TARGET climbsim)
  install(TARGETS climbsim RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT dev)
endif()

install(EXPORT climbsimTargets NAMESPACE climbsim:: DESTINATION ${CLIMBSIM_INSTALL_CMAKEDIR}
        COMPONENT dev)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/climbsimConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/climbsimConfig.cmake
                              INSTALL_DESTINATION ${CLIMBSIM_INSTALL_CMAKEDIR}
                              PATH_VARS CLIMBSIM_INSTALL_DATADIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/climbsimConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/climbsimConfig.cmake
              ${PROJECT_BINARY_DIR}/climbsimConfigVersion.cmake
        DESTINATION ${CLIMBSIM_INSTALL_CMAKEDIR} COMPONENT dev)
