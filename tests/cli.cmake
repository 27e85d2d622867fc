# cli.cmake -- the gigatet CLI's end-to-end tests: every tests/cli/test_*.sh is one ctest
# named cli_<name>, run as `bash SCRIPT PATH/TO/gigatet`.  Exit 77 means "skipped" (a python
# module for a read-back test is really missing, or ulimit -v is meaningless under a
# sanitizer); the scripts say so loudly.  Included by tests/CMakeLists.txt.
if(TARGET gigatet_cli)
  find_program(GTET_BASH bash)
  file(GLOB GTET_CLI_TESTS CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/cli/test_*.sh)
  foreach(script ${GTET_CLI_TESTS})
    get_filename_component(name ${script} NAME_WE)
    string(REGEX REPLACE "^test_" "cli_" name ${name})
    add_test(NAME ${name} COMMAND ${GTET_BASH} ${script} $<TARGET_FILE:gigatet_cli>)
    set_tests_properties(${name} PROPERTIES TIMEOUT 300 SKIP_RETURN_CODE 77
                         ENVIRONMENT "GTET_SANITIZE=${GTET_SANITIZE};GTET_TSAN=${GTET_TSAN}")
  endforeach()
endif()
