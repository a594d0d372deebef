# Helpers shared by every library, app and test directory.

# gmc_component_enabled(<name> <out-var>): honours GMC_COMPONENTS (empty = all).
function(gmc_component_enabled name out)
  if(GMC_COMPONENTS STREQUAL "" OR name IN_LIST GMC_COMPONENTS)
    set(${out} TRUE PARENT_SCOPE)
  else()
    set(${out} FALSE PARENT_SCOPE)
  endif()
endfunction()

# Our own code is held to -Wall -Wextra -Werror; third-party headers come in as SYSTEM.
function(gmc_set_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Werror)
endfunction()

# gmc_add_library(<name> SOURCES ... PUBLIC_DEPS ... PRIVATE_DEPS ...)
# Builds target gmc_<name> (alias GmcRgbd::<name>) from libs/<name>/{include,src}.
function(gmc_add_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target gmc_${name})
  add_library(${target} STATIC ${ARG_SOURCES})
  add_library(GmcRgbd::${name} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name} POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:include>)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  gmc_set_warnings(${target})
  install(TARGETS ${target} EXPORT GmcRgbdTargets ARCHIVE DESTINATION lib)
  install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION include)
  set_property(GLOBAL APPEND PROPERTY GMC_EXPORTED_TARGETS ${target})
endfunction()

# gmc_add_app(<exe-name> <app-library-target> <main.cpp>): thin main, skipped when
# its app library is not part of this build.
function(gmc_add_app exe applib main)
  if(NOT TARGET ${applib})
    return()
  endif()
  add_executable(${exe} ${main})
  target_link_libraries(${exe} PRIVATE ${applib})
  gmc_set_warnings(${exe})
  install(TARGETS ${exe} RUNTIME DESTINATION bin)
endfunction()

# gmc_add_test(<lib> SOURCES ...): one GoogleTest binary per library.
function(gmc_add_test lib)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  set(target test_${lib})
  add_executable(${target} ${ARG_SOURCES})
  target_link_libraries(${target} PRIVATE gmc_${lib} ${ARG_DEPS} GTest::gtest GTest::gtest_main)
  target_compile_definitions(${target} PRIVATE
    GMC_SOURCE_DIR="${PROJECT_SOURCE_DIR}" GMC_BINARY_DIR="${PROJECT_BINARY_DIR}")
  gmc_set_warnings(${target})
  gtest_discover_tests(${target} DISCOVERY_TIMEOUT 60
    PROPERTIES ENVIRONMENT "GMC_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
endfunction()

# Installed CMake package: find_package(GmcRgbd) gives GmcRgbd::<lib> targets.
function(gmc_install_package)
  include(CMakePackageConfigHelpers)
  install(EXPORT GmcRgbdTargets NAMESPACE GmcRgbd:: DESTINATION lib/cmake/GmcRgbd)
  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/GmcRgbdConfig.cmake.in
    ${PROJECT_BINARY_DIR}/GmcRgbdConfig.cmake INSTALL_DESTINATION lib/cmake/GmcRgbd)
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/GmcRgbdConfigVersion.cmake
    COMPATIBILITY SameMajorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/GmcRgbdConfig.cmake
    ${PROJECT_BINARY_DIR}/GmcRgbdConfigVersion.cmake DESTINATION lib/cmake/GmcRgbd)
endfunction()

# share/gmc-rgbd/config: the shipped INI files (config/), installed and mirrored in the
# build tree, so build/bin/<app> finds them the way an installed app does
# (<bin>/../share/gmc-rgbd/config, see libs/apps/rgbd_mapping/include/gmc/apps/config_files.h).
function(gmc_share_config)
  file(GLOB_RECURSE _inis RELATIVE "${PROJECT_SOURCE_DIR}/config" "${PROJECT_SOURCE_DIR}/config/*.ini")
  foreach(f IN LISTS _inis)
    configure_file("${PROJECT_SOURCE_DIR}/config/${f}"
                   "${PROJECT_BINARY_DIR}/share/gmc-rgbd/config/${f}" COPYONLY)
  endforeach()
  install(DIRECTORY "${PROJECT_SOURCE_DIR}/config/" DESTINATION share/gmc-rgbd/config
          FILES_MATCHING PATTERN "*.ini")
endfunction()
