# tactile_generate_rtt_typekit(<ros package> MESSAGES <name>... [NESTED <name>...])
#
# rtt_roscomm's ros_generate_rtt_typekit(<ros package>) (its templates and
# create_boost_header.py, as installed with rtt_roscomm) for the named
# messages of the package only, where rtt_roscomm's own typekit packages
# (rtt_sensor_msgs, ...) compile every message of it. Makes the RTT typekit
# rtt-<ros package>-typekit (types "/<ros package>/<name>", "<...>[]") and the
# ROS transport rtt-<ros package>-ros-transport of this catkin package.
#
# How: the package's catkin config (included once per scope, guarded by
# <ros package>_CONFIG_INCLUDED) sets <ros package>_MESSAGE_FILES, the list
# rtt_roscomm's generator walks; it is narrowed to MESSAGES for the call and
# restored afterwards.
#
# NESTED: messages that are members of the named ones only (geometry_msgs/Pose
# in PoseStamped): their boost serialisation headers, which the named ones'
# headers include, made with create_boost_header.py; no type, no compilation.
#
# Appends the header generating targets to TACTILE_RTT_BOOST_HEADER_TARGETS
# (every typekit of the package must wait for all of them: a header of one
# ROS package includes another's).
macro(tactile_generate_rtt_typekit _tgrt_package)
  cmake_parse_arguments(_tgrt "" "" "MESSAGES;NESTED" ${ARGN})
  if(NOT _tgrt_MESSAGES)
    message(FATAL_ERROR "tactile_generate_rtt_typekit(${_tgrt_package}): no MESSAGES given")
  endif()
  find_package(${_tgrt_package} REQUIRED)
  set(_tgrt_all ${${_tgrt_package}_MESSAGE_FILES})
  set(_tgrt_chosen)
  foreach(_tgrt_msg ${_tgrt_MESSAGES} ${_tgrt_NESTED})
    list(FIND _tgrt_all "msg/${_tgrt_msg}.msg" _tgrt_index)
    if(_tgrt_index LESS 0)
      message(FATAL_ERROR "tactile_generate_rtt_typekit: ${_tgrt_package} has no message ${_tgrt_msg} "
                          "(${${_tgrt_package}_DIR}/../msg; ${_tgrt_package}_MESSAGE_FILES: ${_tgrt_all})")
    endif()
  endforeach()
  foreach(_tgrt_msg ${_tgrt_MESSAGES})
    list(APPEND _tgrt_chosen "msg/${_tgrt_msg}.msg")
  endforeach()
  set(${_tgrt_package}_MESSAGE_FILES ${_tgrt_chosen})
  ros_generate_rtt_typekit(${_tgrt_package})
  set(${_tgrt_package}_MESSAGE_FILES ${_tgrt_all})
  list(APPEND TACTILE_RTT_BOOST_HEADER_TARGETS rtt-${_tgrt_package}-generate_boost_headers)

  if(_tgrt_NESTED)
    rtt_roscomm_destinations()
    set(_tgrt_headers)
    foreach(_tgrt_msg ${_tgrt_NESTED})
      set(_tgrt_file "${${_tgrt_package}_DIR}/../msg/${_tgrt_msg}.msg")
      set(_tgrt_header "${rtt_roscomm_GENERATED_HEADERS_OUTPUT_DIRECTORY}/orocos/${_tgrt_package}/boost/${_tgrt_msg}.h")
      add_custom_command(
        OUTPUT ${_tgrt_header}
        COMMAND ${rtt_roscomm_SCRIPTS_DIR}/create_boost_header.py ${_tgrt_package} "${_tgrt_package}/${_tgrt_msg}"
                ${_tgrt_file} ${_tgrt_header}
        DEPENDS ${_tgrt_file} ${rtt_roscomm_SCRIPTS_DIR}/create_boost_header.py
        VERBATIM)
      list(APPEND _tgrt_headers ${_tgrt_header})
    endforeach()
    add_custom_target(rtt-${_tgrt_package}-nested_boost_headers DEPENDS ${_tgrt_headers})
    list(APPEND TACTILE_RTT_BOOST_HEADER_TARGETS rtt-${_tgrt_package}-nested_boost_headers)
  endif()
endmacro()
