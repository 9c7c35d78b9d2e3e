# ctest driver: run the OCL deployer on one script or deployment XML,
# non-interactively, and check its exit code and output.
#   cmake -DDEPLOYER=... -DSCRIPT=x.ops -DEXPECT_RC=0 -DEXPECT_REGEX=... [-DCHECK_ONLY=ON]
#         [-DLOGLEVEL=warning] [-DFORBID_REGEX=...] -P run_deployer.cmake
# Scripts (.ops) run with --check: the deployer runs the script and then exits
# by its normal shutdown (components stopped, cleaned up, unloaded; no prompt,
# no waiting for ^C) with 0, or 255 when the script failed to parse. The test
# scripts end with the checkpoint `var int all_checks_passed(Check.finish())`
# and the deployment scripts with `var int x(Guard.verdict())`: -1 there (a
# failed check or step) is a parse error, hence exit 255.
# CHECK_ONLY passes --check to a .xml/.cpf deployment: the deployer loads,
# connects and configures it (no start) and exits 0, or 255 when a component
# does not load, a property file fails or configure() returns false.
# UNPRIVILEGED runs the deployer without real-time rights: RLIMIT_RTPRIO 0 and
# RLIMIT_MEMLOCK 64 KiB (prlimit), as user nobody when ctest runs as root
# (setpriv, no capabilities): RTT's rule then refuses SCHED_FIFO and falls
# back to SCHED_OTHER, and mlockall fails.
# The regexes are matched against stdout and stderr (where RTT logs) together.
if(NOT DEFINED TIMEOUT_S)
  set(TIMEOUT_S 30)
endif()
if(NOT DEFINED LOGLEVEL)
  set(LOGLEVEL warning)
endif()
set(extra_args)
if(CHECK_ONLY OR SCRIPT MATCHES "\\.ops$")
  list(APPEND extra_args --check)
endif()
set(wrap)
if(UNPRIVILEGED)
  execute_process(COMMAND id -u OUTPUT_VARIABLE uid OUTPUT_STRIP_TRAILING_WHITESPACE)
  if("${uid}" STREQUAL "0")
    set(wrap setpriv --reuid=65534 --regid=65534 --clear-groups --inh-caps=-all --bounding-set=-all)
  endif()
  list(APPEND wrap prlimit --rtprio=0 --memlock=65536)
endif()
execute_process(COMMAND ${wrap} ${DEPLOYER} ${extra_args} -l${LOGLEVEL} -s ${SCRIPT}
                INPUT_FILE /dev/null
                OUTPUT_VARIABLE out ERROR_VARIABLE err
                RESULT_VARIABLE rc
                TIMEOUT ${TIMEOUT_S})
message("---- deployer stdout ----\n${out}\n---- deployer stderr ----\n${err}\n---- exit: ${rc}")
if(NOT "${rc}" STREQUAL "${EXPECT_RC}")
  message(FATAL_ERROR "deployer exit code ${rc}, expected ${EXPECT_RC}")
endif()
if(NOT "${out}\n${err}" MATCHES "${EXPECT_REGEX}")
  message(FATAL_ERROR "deployer output does not match '${EXPECT_REGEX}'")
endif()
if(DEFINED FORBID_REGEX AND NOT "${FORBID_REGEX}" STREQUAL "" AND "${out}\n${err}" MATCHES "${FORBID_REGEX}")
  message(FATAL_ERROR "deployer output matches the forbidden '${FORBID_REGEX}': '${CMAKE_MATCH_0}'")
endif()
