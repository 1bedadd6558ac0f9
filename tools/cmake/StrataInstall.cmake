# `cmake --install`: the libraries this build made, their public headers under include/strata (so the
# headers' own "physics/..." includes resolve), and the CMake package Strata with targets strata::physics,
# strata::navmesh and strata::assets (components of the same names).
include(CMakePackageConfigHelpers)

set(STRATA_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/Strata)
set(STRATA_COMPONENTS physics)
if(STRATA_BUILD_NAVMESH)
  list(APPEND STRATA_COMPONENTS navmesh)
endif()
if(STRATA_BUILD_ASSETS)
  list(APPEND STRATA_COMPONENTS assets)
endif()

foreach(component IN LISTS STRATA_COMPONENTS)
  install(TARGETS strata_${component} EXPORT StrataTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  file(GLOB_RECURSE headers RELATIVE ${PROJECT_SOURCE_DIR} CONFIGURE_DEPENDS
       ${PROJECT_SOURCE_DIR}/${component}/*.h)
  foreach(header IN LISTS headers)
    get_filename_component(folder ${header} DIRECTORY)
    install(FILES ${PROJECT_SOURCE_DIR}/${header} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/strata/${folder})
  endforeach()
endforeach()

install(EXPORT StrataTargets NAMESPACE strata:: DESTINATION ${STRATA_INSTALL_CMAKEDIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/StrataConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/StrataConfig.cmake
                              INSTALL_DESTINATION ${STRATA_INSTALL_CMAKEDIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/StrataConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/StrataConfig.cmake ${PROJECT_BINARY_DIR}/StrataConfigVersion.cmake
              ${CMAKE_CURRENT_LIST_DIR}/StrataFindRecast.cmake
        DESTINATION ${STRATA_INSTALL_CMAKEDIR})
