# python.cmake -- the Python module's test (tests/python/): one ctest, python_module, that
# builds the extension with pip into a venv of Debian's /usr/bin/python3 under the build tree
# (BUILD/python-venv, objects in BUILD/python-build) and runs tests/python with pytest: against
# scipy, hypothesis properties, the interface, leaks.  Skipped (77) when a python3-* package is
# missing.  Not in sanitizer builds: the extension is compiled by setuptools, without them.
# Included by tests/CMakeLists.txt.
if(NOT GTET_SANITIZE AND NOT GTET_TSAN AND EXISTS /usr/bin/python3)
  find_program(GTET_BASH bash)
  add_test(NAME python_module
           COMMAND ${GTET_BASH} ${CMAKE_CURRENT_SOURCE_DIR}/python/run_tests.sh
                   ${PROJECT_SOURCE_DIR} ${CMAKE_BINARY_DIR})
  set_tests_properties(python_module PROPERTIES TIMEOUT 600 SKIP_RETURN_CODE 77 LABELS python)
  if(TARGET cgal_dt)  # tests/python/test_cgal.py: gigatet's simplices equal CGAL's on grids
    set_tests_properties(python_module PROPERTIES ENVIRONMENT "GTET_CGAL_DT=$<TARGET_FILE:cgal_dt>")
  endif()
endif()
