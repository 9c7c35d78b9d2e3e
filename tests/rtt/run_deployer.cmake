# ctest driver: run the OCL deployer on one script or deployment XML,
# non-interactively, and check its exit code and output.
#   cmake -DDEPLOYER=... -DSCRIPT=x.ops -DEXPECT_RC=0 -DEXPECT_REGEX=... [-DCHECK_ONLY=ON]
#         [-DLOGLEVEL=warning] [-DFORBID_REGEX=...] -P run_deployer.cmake
# The scripts end with OpsCheck.finish(), which exits with the verdict; a script
# that stops early (parse error) leaves the deployer waiting for ^C, which the
# TIMEOUT below (30 s) turns into a failure.
# CHECK_ONLY passes --check: the deployer loads, connects and configures a
# .xml/.cpf deployment (no start, no prompt) and exits 0, or 255 when a
# component does not load, a property file fails or configure() returns false.
# The regexes are matched against stdout and stderr (where RTT logs) together.
if(NOT DEFINED LOGLEVEL)
  set(LOGLEVEL warning)
endif()
set(extra_args)
if(CHECK_ONLY)
  list(APPEND extra_args --check)
endif()
execute_process(COMMAND ${DEPLOYER} ${extra_args} -l${LOGLEVEL} -s ${SCRIPT}
                INPUT_FILE /dev/null
                OUTPUT_VARIABLE out ERROR_VARIABLE err
                RESULT_VARIABLE rc
                TIMEOUT 30)
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
