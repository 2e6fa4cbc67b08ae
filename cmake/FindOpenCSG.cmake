# Finds OpenCSG (Debian: libopencsg-dev), which ships no CMake package: the imported target
# OpenCSG::OpenCSG. Used by fuzzycsg's build and by its installed package (the opencsg module).
find_path(OPENCSG_INCLUDE_DIR opencsg.h)
find_library(OPENCSG_LIBRARY opencsg)
mark_as_advanced(OPENCSG_INCLUDE_DIR OPENCSG_LIBRARY)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(OpenCSG REQUIRED_VARS OPENCSG_LIBRARY OPENCSG_INCLUDE_DIR)

if(OpenCSG_FOUND AND NOT TARGET OpenCSG::OpenCSG)
  add_library(OpenCSG::OpenCSG UNKNOWN IMPORTED)
  set_target_properties(OpenCSG::OpenCSG PROPERTIES IMPORTED_LOCATION ${OPENCSG_LIBRARY}
                        INTERFACE_INCLUDE_DIRECTORIES ${OPENCSG_INCLUDE_DIR})
endif()
