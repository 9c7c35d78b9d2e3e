# The ROS 1 face (ros/): built only where the RTT layer is on, Debian's catkin
# and roscore are installed and rtt_ros_integration is in
# TACTILE_ROS_PREFIX (default <Orocos prefix>/ros, scripts/setup/setup_rtt_ros.sh).
# ros/ is a catkin workspace of its own (tactile_msgs, rtt_tactile_msgs,
# tactile_ros), configured and built as an external project into
# <build>/ros (devel space <build>/ros/devel) after tactile_types.
# Sets TACTILE_ROS_ENABLED, TACTILE_ROS_DEVEL, TACTILE_ROS_PREFIX_DIR.
set(TACTILE_ROS_ENABLED OFF)
set(TACTILE_ROS_PREFIX "" CACHE PATH "rtt_ros_integration install space (empty: <Orocos prefix>/ros)")
get_filename_component(TACTILE_ROS_OROCOS_PREFIX "${OROCOS-RTT_DIR}/../../.." ABSOLUTE)
if(TACTILE_ROS_PREFIX)
  set(TACTILE_ROS_PREFIX_DIR "${TACTILE_ROS_PREFIX}")
else()
  set(TACTILE_ROS_PREFIX_DIR "${TACTILE_ROS_OROCOS_PREFIX}/ros")
endif()
find_file(TACTILE_CATKIN_TOPLEVEL toplevel.cmake PATHS /usr/share/catkin/cmake NO_DEFAULT_PATH)
find_program(TACTILE_ROSCORE roscore)
set(_tactile_ros_missing)
if(NOT TACTILE_CATKIN_TOPLEVEL)
  list(APPEND _tactile_ros_missing "catkin (Debian package catkin)")
endif()
if(NOT TACTILE_ROSCORE)
  list(APPEND _tactile_ros_missing "roscore (Debian package ros-core-dev)")
endif()
if(NOT EXISTS "${TACTILE_ROS_PREFIX_DIR}/share/rtt_roscomm/cmake/rtt_roscommConfig.cmake")
  list(APPEND _tactile_ros_missing "rtt_ros_integration in ${TACTILE_ROS_PREFIX_DIR} (scripts/setup/setup_rtt_ros.sh)")
endif()
if(_tactile_ros_missing)
  string(REPLACE ";" ", " _tactile_ros_missing "${_tactile_ros_missing}")
  if(TACTILE_WITH_ROS STREQUAL "ON")
    message(FATAL_ERROR "tactile_servo: TACTILE_WITH_ROS=ON but not found: ${_tactile_ros_missing}")
  endif()
  message(STATUS "tactile_servo: ROS face OFF (skipped, not found: ${_tactile_ros_missing}); "
                 "the ROS tests are not configured")
  return()
endif()
set(TACTILE_ROS_ENABLED ON)
set(TACTILE_ROS_DEVEL ${CMAKE_BINARY_DIR}/ros/devel)
message(STATUS "tactile_servo: ROS face ON (rtt_ros_integration in ${TACTILE_ROS_PREFIX_DIR}, devel space ${TACTILE_ROS_DEVEL})")
include(ExternalProject)
set(_tactile_ros_launcher)
if(CMAKE_CXX_COMPILER_LAUNCHER)
  set(_tactile_ros_launcher -DCMAKE_CXX_COMPILER_LAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER})
endif()
if(CMAKE_CXX_LINKER_LAUNCHER)
  list(APPEND _tactile_ros_launcher -DCMAKE_CXX_LINKER_LAUNCHER=${CMAKE_CXX_LINKER_LAUNCHER})
endif()
# The workspace's environment (what sourcing the install space's setup.sh
# gives, for the build only): Debian's python3 first (the generators of
# genmsg and rtt_roscomm run as `python3`), the Orocos packages' pkg-config
# files (UseOROCOS-RTT finds the rtt_ros packages with pkg-config).
set(_tactile_ros_env ${CMAKE_COMMAND} -E env "PATH=/usr/bin:$ENV{PATH}"
    "PKG_CONFIG_PATH=${TACTILE_ROS_PREFIX_DIR}/lib/pkgconfig:${TACTILE_ROS_OROCOS_PREFIX}/lib/pkgconfig:$ENV{PKG_CONFIG_PATH}")
# Makefiles: the parent make's $(MAKE) (shares its job server); other
# generators (Ninja): cmake --build on the workspace, same generator.
if(CMAKE_GENERATOR MATCHES "Makefiles")
  set(_tactile_ros_build ${_tactile_ros_env} $(MAKE))
else()
  set(_tactile_ros_build ${_tactile_ros_env} ${CMAKE_COMMAND} --build <BINARY_DIR>)
endif()
ExternalProject_Add(tactile_ros_ws
  SOURCE_DIR ${PROJECT_SOURCE_DIR}/ros
  BINARY_DIR ${CMAKE_BINARY_DIR}/ros/build
  LIST_SEPARATOR |
  CMAKE_COMMAND ${_tactile_ros_env} ${CMAKE_COMMAND}
  BUILD_COMMAND ${_tactile_ros_build}
  CMAKE_ARGS -DCMAKE_BUILD_TYPE=Release
             -DCMAKE_PREFIX_PATH=${TACTILE_ROS_PREFIX_DIR}|${TACTILE_ROS_OROCOS_PREFIX}
             -DCATKIN_DEVEL_PREFIX=${TACTILE_ROS_DEVEL}
             -DCATKIN_TOPLEVEL_CMAKE=${TACTILE_CATKIN_TOPLEVEL}
             -DPYTHON_EXECUTABLE=/usr/bin/python3 -DCATKIN_ENABLE_TESTING=OFF
             -DTACTILE_SOURCE_DIR=${PROJECT_SOURCE_DIR}
             -DTACTILE_TYPES_LIBRARY=$<TARGET_FILE:tactile_types>
             -DTACTILE_BUILD_TESTS=${TACTILE_BUILD_TESTS}
             ${_tactile_ros_launcher}
             # The project's compile and link flags (e.g. scripts/realtime/sanitize.sh's
             # -fsanitize=...): the ROS face links the project's libraries.
             "-DCMAKE_C_FLAGS=${CMAKE_C_FLAGS}" "-DCMAKE_CXX_FLAGS=${CMAKE_CXX_FLAGS}"
             "-DCMAKE_EXE_LINKER_FLAGS=${CMAKE_EXE_LINKER_FLAGS}" "-DCMAKE_SHARED_LINKER_FLAGS=${CMAKE_SHARED_LINKER_FLAGS}"
  INSTALL_COMMAND ""
  BUILD_ALWAYS ON
  DEPENDS tactile_types)
