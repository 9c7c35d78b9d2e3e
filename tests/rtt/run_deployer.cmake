# ctest driver: run the OCL deployer on one script, non-interactively, and
# check its exit code and output.
#   cmake -DDEPLOYER=... -DSCRIPT=x.ops -DEXPECT_RC=0 -DEXPECT_REGEX=... -P run_deployer.cmake
# The scripts end with OpsCheck.finish(), which exits with the verdict; a script
# that stops early (parse error) leaves the deployer waiting for ^C, which the
# TIMEOUT below (30 s) turns into a failure.
execute_process(COMMAND ${DEPLOYER} -lwarning -s ${SCRIPT}
                INPUT_FILE /dev/null
                OUTPUT_VARIABLE out ERROR_VARIABLE err
                RESULT_VARIABLE rc
                TIMEOUT 30)
message("---- deployer stdout ----\n${out}\n---- deployer stderr ----\n${err}\n---- exit: ${rc}")
if(NOT "${rc}" STREQUAL "${EXPECT_RC}")
  message(FATAL_ERROR "deployer exit code ${rc}, expected ${EXPECT_RC}")
endif()
if(NOT "${out}" MATCHES "${EXPECT_REGEX}")
  message(FATAL_ERROR "deployer output does not match '${EXPECT_REGEX}'")
endif()
