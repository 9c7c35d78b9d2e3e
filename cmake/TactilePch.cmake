# Precompiled RTT headers for the RTT layer (docs/build_times.md).
#
# Every RTT library and RTT test parses the same few thousand lines of RTT and
# Boost headers (about 3 CPU s per source file). tactile_rtt_pch(<target> LIB|TEST)
# gives <target> one shared precompiled header, built once per kind:
#   LIB   shared libraries (components, typekit; -fPIC): host tactile_rtt_pch_lib
#   TEST  test and benchmark executables (-fPIE; adds gtest): host tactile_rtt_pch_test
# A host is a tiny target with only the flags every user has (OROCOS_TARGET);
# GCC takes a precompiled header only where the flags match and every macro it
# was built with is defined alike (extra -D of the users are fine).
# Off by default: measured, a source file compiles about as fast with it as
# without (the headers are a few seconds of a 20-110 s RTT source file, the
# 220-270 MB precompiled header takes about as long to load; docs/build_times.md).
# -DTACTILE_PCH=ON to measure it again.
option(TACTILE_PCH "Precompiled RTT headers for the RTT libraries and tests" OFF)

set(TACTILE_RTT_PCH_HEADERS
  <rtt/TaskContext.hpp> <rtt/InputPort.hpp> <rtt/OutputPort.hpp> <rtt/Activity.hpp>
  <rtt/extras/SlaveActivity.hpp> <rtt/os/TimeService.hpp> <rtt/Logger.hpp>
  <rtt/Attribute.hpp> <rtt/Property.hpp> <rtt/ConnPolicy.hpp>
  <cmath> <string> <vector>)

# ccache caches compiles with a precompiled header only with this sloppiness.
function(_tactile_pch_launcher target)
  if(CMAKE_CXX_COMPILER_LAUNCHER MATCHES "ccache")
    set_target_properties(${target} PROPERTIES CXX_COMPILER_LAUNCHER
      "/usr/bin/env;CCACHE_SLOPPINESS=pch_defines,time_macros,include_file_mtime,include_file_ctime;${CMAKE_CXX_COMPILER_LAUNCHER}")
  endif()
endfunction()

function(_tactile_rtt_pch_host kind)
  set(host tactile_rtt_pch_${kind})
  if(TARGET ${host})
    return()
  endif()
  set(src ${PROJECT_SOURCE_DIR}/cmake/pch/pch_host.cpp)
  if(kind STREQUAL "lib")
    add_library(${host} OBJECT ${src})
    target_precompile_headers(${host} PRIVATE ${TACTILE_RTT_PCH_HEADERS})
  else()
    add_executable(${host} ${src})
    target_link_libraries(${host} PRIVATE ${OROCOS-RTT_LIBRARIES} GTest::gtest)
    target_precompile_headers(${host} PRIVATE ${TACTILE_RTT_PCH_HEADERS} <gtest/gtest.h>)
  endif()
  target_include_directories(${host} SYSTEM PRIVATE ${OROCOS-RTT_INCLUDE_DIRS})
  target_compile_definitions(${host} PRIVATE OROCOS_TARGET=${OROCOS_TARGET})
  tactile_warnings(${host})
  _tactile_pch_launcher(${host})
endfunction()

function(tactile_rtt_pch target kind)
  if(NOT TACTILE_PCH)
    return()
  endif()
  string(TOLOWER ${kind} kind)
  _tactile_rtt_pch_host(${kind})
  target_precompile_headers(${target} REUSE_FROM tactile_rtt_pch_${kind})
  _tactile_pch_launcher(${target})
endfunction()
