# `cmake --install` (and the .deb CPack makes from it): the programs, the
# systemd units and their settings file, the reference DDS configs, and
# hapsim::core with its headers and an exported CMake package, so another
# project can `find_package(hapsim)` and link `hapsim::core`.
# Places are FHS (GNUInstallDirs): with the prefix /usr, programs in
# /usr/bin, settings in /etc/hapsim, units in /usr/lib/systemd/system.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# The programs a lab runs (those this build made).
foreach(_program IN ITEMS hapsim-server hapsim-bridge hapsim-load hapsim-viewer hapsim-ctl hapsim-replay
                          hapsim-validate)
  if(TARGET ${_program})
    install(TARGETS ${_program} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
  endif()
endforeach()
if(TARGET hapsim-server)
  # The units name the installed programs and settings by their full paths.
  foreach(_unit IN ITEMS hapsim-server.service hapsim-bridge@.service)
    configure_file(${PROJECT_SOURCE_DIR}/deploy/systemd/${_unit}.in ${PROJECT_BINARY_DIR}/deploy/systemd/${_unit} @ONLY)
    install(FILES ${PROJECT_BINARY_DIR}/deploy/systemd/${_unit}
            DESTINATION ${CMAKE_INSTALL_PREFIX}/lib/systemd/system COMPONENT runtime)
  endforeach()
  # Settings: config files in /etc are kept over upgrades by dpkg (conffiles).
  install(FILES ${PROJECT_SOURCE_DIR}/deploy/systemd/server.env ${PROJECT_SOURCE_DIR}/deploy/systemd/bridge.env
          DESTINATION ${CMAKE_INSTALL_FULL_SYSCONFDIR}/hapsim COMPONENT runtime)
  install(FILES ${PROJECT_SOURCE_DIR}/deploy/cyclonedds-loopback.xml
          DESTINATION ${CMAKE_INSTALL_DATADIR}/hapsim COMPONENT runtime)
  install(FILES ${PROJECT_SOURCE_DIR}/docs/deploy.md ${PROJECT_SOURCE_DIR}/README.md
          DESTINATION ${CMAKE_INSTALL_DOCDIR} COMPONENT runtime)
  install(PROGRAMS ${PROJECT_SOURCE_DIR}/deploy/make-dds-config.sh ${PROJECT_SOURCE_DIR}/deploy/make-class.sh
                   ${PROJECT_SOURCE_DIR}/deploy/make-dev-certs.sh
          DESTINATION ${CMAKE_INSTALL_DATADIR}/hapsim COMPONENT runtime)
endif()

# hapsim::core for other projects: the static library, its headers, and
# hapsimConfig.cmake (Eigen 3.4 found for the consumer).
set_target_properties(hapsim_core PROPERTIES EXPORT_NAME core)
install(TARGETS hapsim_core EXPORT hapsimTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT development
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/core/include/hapsim DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        COMPONENT development)
set(HAPSIM_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/hapsim)
install(EXPORT hapsimTargets NAMESPACE hapsim:: DESTINATION ${HAPSIM_CMAKE_DIR} COMPONENT development)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/hapsimConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/hapsimConfig.cmake INSTALL_DESTINATION ${HAPSIM_CMAKE_DIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/hapsimConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/hapsimConfig.cmake ${PROJECT_BINARY_DIR}/hapsimConfigVersion.cmake
        DESTINATION ${HAPSIM_CMAKE_DIR} COMPONENT development)
