# Shared CMake of the RTT layer (included by every CMakeLists.txt under rtt/).
#
# Layout, in the build tree and installed alike (RTT's component search layout):
#   <root>/lib/orocos/<OROCOS_TARGET>/tactile/lib<name>-<target>.so         components
#   <root>/lib/orocos/<OROCOS_TARGET>/tactile/types/lib<name>-<target>.so   typekit
# so RTT_COMPONENT_PATH=<root>/lib/orocos and `import("tactile")` in a
# deployment script load all of them.

include(${PROJECT_SOURCE_DIR}/cmake/TactilePch.cmake)  # tactile_rtt_pch()

set(TACTILE_RTT_PACKAGE tactile)
set(TACTILE_RTT_COMPONENT_PATH ${CMAKE_BINARY_DIR}/lib/orocos)
set(TACTILE_RTT_PACKAGE_DIR ${TACTILE_RTT_COMPONENT_PATH}/${OROCOS_TARGET}/${TACTILE_RTT_PACKAGE})
set(TACTILE_RTT_INSTALL_DIR lib/orocos/${OROCOS_TARGET}/${TACTILE_RTT_PACKAGE})
# Directory of RTT's own typekit library (.../rtt/types), for in-process tests.
get_target_property(_tactile_rtt_tk_loc ${OROCOS-RTT_TYPEKIT_LIBRARIES} IMPORTED_LOCATION_RELEASE)
if(NOT _tactile_rtt_tk_loc)
  get_target_property(_tactile_rtt_tk_loc ${OROCOS-RTT_TYPEKIT_LIBRARIES} LOCATION)
endif()
get_filename_component(_tactile_rtt_tk_dir "${_tactile_rtt_tk_loc}" DIRECTORY)
get_filename_component(TACTILE_RTT_OWN_PACKAGE_DIR "${_tactile_rtt_tk_dir}" DIRECTORY)  # .../<target>/rtt
get_filename_component(_tactile_rtt_tdir "${TACTILE_RTT_OWN_PACKAGE_DIR}" DIRECTORY)
get_filename_component(TACTILE_RTT_SYSTEM_COMPONENT_PATH "${_tactile_rtt_tdir}" DIRECTORY)  # .../lib/orocos

# tactile_rtt_library(<target> COMPONENT|TYPEKIT|TEST_COMPONENT SOURCES...)
# TEST_COMPONENT: a component library for the tests only, in package
# "tactile_test" of the build tree, not installed.
function(tactile_rtt_library target kind)
  add_library(${target} SHARED ${ARGN})
  target_include_directories(${target} SYSTEM PUBLIC ${OROCOS-RTT_INCLUDE_DIRS})
  # tactile_types_rtt/ (atomic_attribute.hpp) for every RTT library.
  target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/rtt/typekit/include>)
  target_compile_definitions(${target} PUBLIC OROCOS_TARGET=${OROCOS_TARGET})
  target_link_libraries(${target} PUBLIC ${OROCOS-RTT_LIBRARIES})
  tactile_warnings(${target})
  tactile_rtt_pch(${target} LIB)
  set(dir ${TACTILE_RTT_PACKAGE_DIR})
  set(inst ${TACTILE_RTT_INSTALL_DIR})
  if(kind STREQUAL "TYPEKIT")
    set(dir ${dir}/types)
    set(inst ${inst}/types)
  elseif(kind STREQUAL "COMPONENT" OR kind STREQUAL "TEST_COMPONENT")
    # ORO_CREATE_COMPONENT_LIBRARY exports the factory symbols only with RTT_COMPONENT.
    target_compile_definitions(${target} PRIVATE RTT_COMPONENT)
    if(kind STREQUAL "TEST_COMPONENT")
      set(dir ${TACTILE_RTT_COMPONENT_PATH}/${OROCOS_TARGET}/tactile_test)
      set(inst "")
    endif()
  else()
    message(FATAL_ERROR "tactile_rtt_library: kind must be COMPONENT, TYPEKIT or TEST_COMPONENT, got '${kind}'")
  endif()
  set_target_properties(${target} PROPERTIES
    OUTPUT_NAME ${target}-${OROCOS_TARGET}
    LIBRARY_OUTPUT_DIRECTORY ${dir}
    INSTALL_RPATH "${CMAKE_INSTALL_PREFIX}/lib"
    INSTALL_RPATH_USE_LINK_PATH TRUE)  # liborocos-rtt etc. from their install dirs
  if(inst)
    install(TARGETS ${target} LIBRARY DESTINATION ${inst})
    # Its headers (include/), for code that links or extends it.
    if(IS_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include)
      install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION include)
    endif()
    set_property(GLOBAL APPEND PROPERTY TACTILE_RTT_INSTALLED_${kind} ${target}-${OROCOS_TARGET})
  endif()
endfunction()

# tactile_rtt_generate_package(): <prefix>/lib/pkgconfig/tactile-<target>.pc for
# the installed typekit and components, in the form of UseOROCOS-RTT's
# orocos_generate_package() (orocos_libdir = the package directory, -l of each
# component, types/ for the typekit), but relocatable (prefix from the .pc's
# own location) and with the headers in <prefix>/include.
function(tactile_rtt_generate_package)
  get_property(comps GLOBAL PROPERTY TACTILE_RTT_INSTALLED_COMPONENT)
  get_property(types GLOBAL PROPERTY TACTILE_RTT_INSTALLED_TYPEKIT)
  set(libs "")
  if(comps)
    list(TRANSFORM comps PREPEND "-l")
    list(JOIN comps " " comps)
    string(APPEND libs " -L\${orocos_libdir} ${comps}")
  endif()
  if(types)
    list(TRANSFORM types PREPEND "-l")
    list(JOIN types " " types)
    string(APPEND libs " -L\${orocos_libdir}/types ${types}")
  endif()
  set(pc_name ${TACTILE_RTT_PACKAGE}-${OROCOS_TARGET})
  file(WRITE ${CMAKE_BINARY_DIR}/${pc_name}.pc
"# Orocos package '${TACTILE_RTT_PACKAGE}' of tactile_servo (typekit and components).
prefix=\${pcfiledir}/../..
libdir=\${prefix}/lib
includedir=\${prefix}/include
orocos_libdir=\${libdir}/orocos/${OROCOS_TARGET}/${TACTILE_RTT_PACKAGE}

Name: ${pc_name}
Description: ${pc_name} package for Orocos (tactile_servo's typekit and components)
Requires: orocos-rtt-${OROCOS_TARGET} eigen3 orocos-kdl yaml-cpp
Version: ${PROJECT_VERSION}
Libs:${libs}
Cflags: -I\${includedir}
")
  install(FILES ${CMAKE_BINARY_DIR}/${pc_name}.pc DESTINATION lib/pkgconfig)
endfunction()
