# Imported targets RecastNavigation::Recast, ::Detour and ::DetourCrowd (the names upstream's own package
# exports) for a Recast/Detour installed without a CMake package, as Debian's librecast-dev is. Used by the
# build and by the installed StrataConfig.cmake.
if(NOT TARGET RecastNavigation::Detour)
  find_path(STRATA_RECAST_INCLUDE_DIR Recast.h PATH_SUFFIXES recastnavigation REQUIRED)
  find_library(STRATA_RECAST_LIBRARY Recast REQUIRED)
  find_library(STRATA_DETOUR_LIBRARY Detour REQUIRED)
  find_library(STRATA_DETOURCROWD_LIBRARY DetourCrowd REQUIRED)
  foreach(part Recast Detour DetourCrowd)
    string(TOUPPER ${part} upper)
    add_library(RecastNavigation::${part} UNKNOWN IMPORTED)
    set_target_properties(RecastNavigation::${part} PROPERTIES
      IMPORTED_LOCATION "${STRATA_${upper}_LIBRARY}"
      INTERFACE_INCLUDE_DIRECTORIES "${STRATA_RECAST_INCLUDE_DIR}")
  endforeach()
endif()
set_property(TARGET RecastNavigation::DetourCrowd APPEND PROPERTY INTERFACE_LINK_LIBRARIES RecastNavigation::Detour)
