# Install and export: headers, the components' libraries, the executables, configs/, the formats' docs
# and schemas, and a toolincConfig.cmake (with version file) usable from the install prefix and, through
# export(), from the build tree:  find_package(toolinc 0.1 REQUIRED COMPONENTS results)
include(CMakePackageConfigHelpers)

set(TOOLINC_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/toolinc)
set(TOOLINC_EXPORTED_TARGETS "")
foreach(component ${TOOLINC_COMPONENTS})
  list(APPEND TOOLINC_EXPORTED_TARGETS toolinc_${component})
endforeach()
set_target_properties(toolinc PROPERTIES EXPORT_NAME toolinc)

install(TARGETS ${TOOLINC_EXPORTED_TARGETS} toolinc EXPORT toolincTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS ${TOOLINC_APP_TARGETS} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

# Headers, but the command-line glue's.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/toolinc DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}
        FILES_MATCHING PATTERN "*.hpp" PATTERN app EXCLUDE)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/configs/ DESTINATION ${CMAKE_INSTALL_DATADIR}/toolinc/configs)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR})

install(EXPORT toolincTargets NAMESPACE toolinc:: DESTINATION ${TOOLINC_CMAKE_DIR})
export(EXPORT toolincTargets NAMESPACE toolinc:: FILE ${PROJECT_BINARY_DIR}/toolincTargets.cmake)

configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/toolincConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/toolincConfig.cmake INSTALL_DESTINATION ${TOOLINC_CMAKE_DIR})
# 0.x: a minor version may break the interface, so only the same minor version is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/toolincConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/toolincConfig.cmake ${PROJECT_BINARY_DIR}/toolincConfigVersion.cmake
        DESTINATION ${TOOLINC_CMAKE_DIR})
