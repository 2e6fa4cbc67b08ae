# The library modules and their packages. src/CMakeLists.txt
#   1. declares every module with what it links (fuzzycsg_declare_module),
#   2. picks the modules to build (fuzzycsg_resolve_modules: FUZZYCSG_MODULES and the
#      FUZZYCSG_WITH_* options, with every module they link) and finds the packages of those
#      only,
#   3. defines each one (fuzzycsg_module: a static library fuzzycsg_<module>, alias and export
#      name fuzzycsg::<module>), and
#   4. installs them with the CMake package that find_package(fuzzycsg) reads
#      (fuzzycsg_install_modules).
# The link lines given to fuzzycsg_declare_module are the only list of what a module needs: the
# packages to look for, the modules to build with it and the find_dependency calls of the
# installed package all follow from them.

include(CMakePackageConfigHelpers)
include(GNUInstallDirs)

# How each external package is found, by the name its imported targets start with
# (TBB::tbb -> TBB, hwy::hwy_contrib -> hwy, PkgConfig::STB -> STB, embree -> embree).
set(FUZZYCSG_FIND_Eigen3 Eigen3 3.4 NO_MODULE)
set(FUZZYCSG_FIND_TBB TBB)
set(FUZZYCSG_FIND_hwy hwy)
set(FUZZYCSG_FIND_nlohmann_json nlohmann_json 3.10)
set(FUZZYCSG_FIND_fmt fmt)
set(FUZZYCSG_FIND_assimp assimp)
set(FUZZYCSG_FIND_embree embree 3)
set(FUZZYCSG_FIND_nanoflann nanoflann)
# CGAL 5 is header-only; convert uses its shape detection with a double-precision kernel only,
# so without GMP.
set(FUZZYCSG_FIND_CGAL CGAL 5.5)
set(CGAL_DISABLE_GMP ON)
# OpenCSG drawn headless through Mesa's surfaceless EGL platform (src/opencsg). Debian's
# libopencsg links GLEW; OpenCSG has no CMake package of its own (cmake/FindOpenCSG.cmake).
set(FUZZYCSG_FIND_OpenGL OpenGL COMPONENTS OpenGL EGL)
set(FUZZYCSG_FIND_GLEW GLEW)
set(FUZZYCSG_FIND_OpenCSG OpenCSG)
# Found through pkg-config (imported targets PkgConfig::<name>): the pkg-config module.
set(FUZZYCSG_PKGCONFIG_STB stb)
set(FUZZYCSG_PKGCONFIG_GVC libgvc)
set(FUZZYCSG_PKGCONFIG_GIF libgif)
set(FUZZYCSG_PKGCONFIG_CAIRO cairo)

# The package an imported target belongs to.
function(_fuzzycsg_package_of item out)
  if(item MATCHES "^PkgConfig::(.+)$")
    set(${out} ${CMAKE_MATCH_1} PARENT_SCOPE)
  elseif(item MATCHES "^([^:]+)::")
    set(${out} ${CMAKE_MATCH_1} PARENT_SCOPE)
  else()
    set(${out} ${item} PARENT_SCOPE)
  endif()
endfunction()

# fuzzycsg_declare_module(<module> [PUBLIC <item>...] [PRIVATE <item>...]): the module
# src/<module> with the link items of target_link_libraries: fuzzycsg::<module> for other modules
# (declared before it), imported targets of the packages above, and
# $<BUILD_INTERFACE:<target>> for header-only packages that the installed library does not need.
function(fuzzycsg_declare_module name)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "PUBLIC;PRIVATE")
  get_property(declared GLOBAL PROPERTY FUZZYCSG_DECLARED_MODULES)
  set(modules "")
  set(packages "")         # needed to build the module
  set(export_packages "")  # needed by the installed module's users
  foreach(item IN LISTS arg_PUBLIC arg_PRIVATE)
    set(build_only FALSE)
    if(item MATCHES "^\\$<BUILD_INTERFACE:(.+)>$")
      set(item ${CMAKE_MATCH_1})
      set(build_only TRUE)
    endif()
    if(item MATCHES "^\\$<")
      message(FATAL_ERROR "fuzzycsg_declare_module(${name}): unsupported link item ${item}")
    elseif(item MATCHES "^fuzzycsg::(.+)$")
      if(NOT CMAKE_MATCH_1 IN_LIST declared)
        message(FATAL_ERROR "fuzzycsg_declare_module(${name}): ${item} is not declared before it")
      endif()
      list(APPEND modules ${CMAKE_MATCH_1})
    else()
      _fuzzycsg_package_of(${item} package)
      if(NOT DEFINED FUZZYCSG_FIND_${package} AND NOT DEFINED FUZZYCSG_PKGCONFIG_${package})
        message(FATAL_ERROR "fuzzycsg_declare_module(${name}): no way to find the package of "
                            "${item} (cmake/FuzzycsgModules.cmake)")
      endif()
      list(APPEND packages ${package})
      if(NOT build_only)
        list(APPEND export_packages ${package})
      endif()
    endif()
  endforeach()
  list(REMOVE_DUPLICATES modules)
  list(REMOVE_DUPLICATES packages)
  list(REMOVE_DUPLICATES export_packages)
  set_property(GLOBAL APPEND PROPERTY FUZZYCSG_DECLARED_MODULES ${name})
  set_property(GLOBAL PROPERTY FUZZYCSG_${name}_PUBLIC ${arg_PUBLIC})
  set_property(GLOBAL PROPERTY FUZZYCSG_${name}_PRIVATE ${arg_PRIVATE})
  set_property(GLOBAL PROPERTY FUZZYCSG_${name}_MODULES ${modules})
  set_property(GLOBAL PROPERTY FUZZYCSG_${name}_PACKAGES ${packages})
  set_property(GLOBAL PROPERTY FUZZYCSG_${name}_EXPORT_PACKAGES ${export_packages})
endfunction()

# Finds a package for the build, once; its imported targets are global, so that the program,
# the tests and the benchmarks see them too.
function(_fuzzycsg_find_package package)
  get_property(found GLOBAL PROPERTY FUZZYCSG_FOUND_${package})
  if(found)
    return()
  endif()
  if(DEFINED FUZZYCSG_PKGCONFIG_${package})
    find_package(PkgConfig REQUIRED)
    pkg_check_modules(${package} REQUIRED IMPORTED_TARGET GLOBAL ${FUZZYCSG_PKGCONFIG_${package}})
  else()
    set(args ${FUZZYCSG_FIND_${package}})
    list(POP_FRONT args name)
    find_package(${name} ${args} REQUIRED GLOBAL)
  endif()
  set_property(GLOBAL PROPERTY FUZZYCSG_FOUND_${package} TRUE)
endfunction()

# The modules to build: FUZZYCSG_MODULES ("all", or a list) with every module they link; "all"
# leaves out diagram without FUZZYCSG_WITH_DIAGRAM and opencsg without FUZZYCSG_WITH_OPENCSG.
# Sets FUZZYCSG_BUILT_MODULES (in dependency order) in the caller and as a global property, and
# finds the packages of those modules.
function(fuzzycsg_resolve_modules)
  get_property(declared GLOBAL PROPERTY FUZZYCSG_DECLARED_MODULES)
  set(disabled "")
  if(NOT FUZZYCSG_WITH_DIAGRAM)
    list(APPEND disabled diagram)
  endif()
  if(NOT FUZZYCSG_WITH_OPENCSG)
    list(APPEND disabled opencsg)
  endif()
  if(FUZZYCSG_MODULES STREQUAL "all")
    set(wanted ${declared})
    list(REMOVE_ITEM wanted ${disabled})
  else()
    set(wanted ${FUZZYCSG_MODULES})
    foreach(m IN LISTS wanted)
      if(NOT m IN_LIST declared)
        string(REPLACE ";" " " shown "${declared}")
        message(FATAL_ERROR "FUZZYCSG_MODULES: no module '${m}' (modules: ${shown})")
      endif()
    endforeach()
  endif()
  # Declared in dependency order: walked backwards, every module's dependencies come after it.
  set(reversed ${declared})
  list(REVERSE reversed)
  foreach(m IN LISTS reversed)
    if(m IN_LIST wanted)
      get_property(deps GLOBAL PROPERTY FUZZYCSG_${m}_MODULES)
      list(APPEND wanted ${deps})
    endif()
  endforeach()
  set(built "")
  foreach(m IN LISTS declared)
    if(m IN_LIST wanted)
      if(m IN_LIST disabled)
        string(TOUPPER ${m} option)
        message(FATAL_ERROR "FUZZYCSG_MODULES asks for the ${m} module, which "
                            "FUZZYCSG_WITH_${option}=OFF leaves out")
      endif()
      list(APPEND built ${m})
    endif()
  endforeach()
  foreach(m IN LISTS built)
    get_property(packages GLOBAL PROPERTY FUZZYCSG_${m}_PACKAGES)
    foreach(p IN LISTS packages)
      _fuzzycsg_find_package(${p})
    endforeach()
  endforeach()
  string(REPLACE ";" " " shown "${built}")
  message(STATUS "fuzzycsg modules: ${shown}")
  set_property(GLOBAL PROPERTY FUZZYCSG_BUILT_MODULES ${built})
  set(FUZZYCSG_BUILT_MODULES ${built} PARENT_SCOPE)
endfunction()

# fuzzycsg_missing_modules(<var> <module>...): those of the modules that are not built, separated
# by spaces (empty when all are).
function(fuzzycsg_missing_modules out)
  get_property(built GLOBAL PROPERTY FUZZYCSG_BUILT_MODULES)
  set(missing "")
  foreach(m IN LISTS ARGN)
    if(NOT m IN_LIST built)
      list(APPEND missing ${m})
    endif()
  endforeach()
  string(REPLACE ";" " " missing "${missing}")
  set(${out} "${missing}" PARENT_SCOPE)
endfunction()

# The static library of a module (when it is built): sources src/<module>/*.cpp, public headers
# include/fuzzycsg/<module>, linked as declared.
function(fuzzycsg_module name)
  get_property(built GLOBAL PROPERTY FUZZYCSG_BUILT_MODULES)
  if(NOT name IN_LIST built)
    return()
  endif()
  file(GLOB _sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${name}/*.cpp)
  if(NOT _sources)
    # A module with no sources yet (partial checkouts) still configures.
    set(_sources ${PROJECT_SOURCE_DIR}/cmake/empty.cpp)
  endif()
  add_library(fuzzycsg_${name} STATIC ${_sources})
  add_library(fuzzycsg::${name} ALIAS fuzzycsg_${name})
  target_include_directories(fuzzycsg_${name} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
                             $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  get_property(public GLOBAL PROPERTY FUZZYCSG_${name}_PUBLIC)
  get_property(private GLOBAL PROPERTY FUZZYCSG_${name}_PRIVATE)
  # The warning and sanitizer flags are the build's own, not the installed library's.
  target_link_libraries(fuzzycsg_${name} PRIVATE $<BUILD_INTERFACE:fuzzycsg::options>)
  target_link_libraries(fuzzycsg_${name} PUBLIC ${public} PRIVATE ${private})
  # A library built with the sanitizers needs their runtimes wherever it is linked.
  if(FUZZYCSG_SANITIZER_LINK_OPTIONS)
    target_link_options(fuzzycsg_${name} INTERFACE
                        $<INSTALL_INTERFACE:${FUZZYCSG_SANITIZER_LINK_OPTIONS}>)
  endif()
  set_target_properties(fuzzycsg_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON EXPORT_NAME ${name})
endfunction()

# Installs the built modules (libraries, headers, one export set each) and the package:
#   <libdir>/cmake/fuzzycsg/fuzzycsgConfig.cmake, fuzzycsgConfigVersion.cmake,
#   fuzzycsg-<module>.cmake (the module's dependencies, then its targets) and
#   fuzzycsg-<module>-targets.cmake.
function(fuzzycsg_install_modules)
  get_property(built GLOBAL PROPERTY FUZZYCSG_BUILT_MODULES)
  set(config_dir ${CMAKE_INSTALL_LIBDIR}/cmake/fuzzycsg)
  set(generated ${PROJECT_BINARY_DIR}/cmake/fuzzycsg)
  set(config_files ${generated}/fuzzycsgConfig.cmake ${generated}/fuzzycsgConfigVersion.cmake)
  foreach(m IN LISTS built)
    install(TARGETS fuzzycsg_${m} EXPORT fuzzycsg-${m}-targets
            ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
    install(EXPORT fuzzycsg-${m}-targets NAMESPACE fuzzycsg:: DESTINATION ${config_dir})
    if(IS_DIRECTORY ${PROJECT_SOURCE_DIR}/include/fuzzycsg/${m})
      install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/fuzzycsg/${m}
              DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/fuzzycsg)
    endif()

    # fuzzycsg-<module>.cmake: the modules it links first, then its packages, then its targets.
    set(text "# fuzzycsg::${m}: the modules and packages it links, then the target (generated by\n")
    string(APPEND text "# fuzzycsg's build, cmake/FuzzycsgModules.cmake).\n")
    string(APPEND text "if(TARGET fuzzycsg::${m})\n  return()\nendif()\n")
    get_property(deps GLOBAL PROPERTY FUZZYCSG_${m}_MODULES)
    foreach(d IN LISTS deps)
      string(APPEND text "include(\"\${CMAKE_CURRENT_LIST_DIR}/fuzzycsg-${d}.cmake\")\n")
      string(APPEND text "if(NOT fuzzycsg_FOUND)\n  return()\nendif()\n")
    endforeach()
    get_property(packages GLOBAL PROPERTY FUZZYCSG_${m}_EXPORT_PACKAGES)
    foreach(p IN LISTS packages)
      if(DEFINED FUZZYCSG_PKGCONFIG_${p})
        string(APPEND text "_fuzzycsg_find_pkgconfig(${m} ${p} ${FUZZYCSG_PKGCONFIG_${p}})\n")
        string(APPEND text "if(NOT fuzzycsg_FOUND)\n  return()\nendif()\n")
      else()
        string(REPLACE ";" " " args "${FUZZYCSG_FIND_${p}}")
        string(APPEND text "find_dependency(${args})\n")
      endif()
    endforeach()
    string(APPEND text "include(\"\${CMAKE_CURRENT_LIST_DIR}/fuzzycsg-${m}-targets.cmake\")\n")
    file(WRITE ${generated}/fuzzycsg-${m}.cmake "${text}")
    list(APPEND config_files ${generated}/fuzzycsg-${m}.cmake)
    if("OpenCSG" IN_LIST packages)
      list(APPEND config_files ${PROJECT_SOURCE_DIR}/cmake/FindOpenCSG.cmake)
    endif()
  endforeach()

  set(FUZZYCSG_INSTALLED_MODULES ${built})
  foreach(option WITH_GIF SANITIZE)
    if(FUZZYCSG_${option})
      set(FUZZYCSG_CONFIG_${option} ON)
    else()
      set(FUZZYCSG_CONFIG_${option} OFF)
    endif()
  endforeach()
  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/fuzzycsgConfig.cmake.in
                                ${generated}/fuzzycsgConfig.cmake INSTALL_DESTINATION ${config_dir}
                                NO_SET_AND_CHECK_MACRO)
  # 0.x: a new minor version may break the interface.
  write_basic_package_version_file(${generated}/fuzzycsgConfigVersion.cmake
                                   COMPATIBILITY SameMinorVersion)
  install(FILES ${config_files} DESTINATION ${config_dir})
endfunction()
