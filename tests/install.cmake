# install.cmake -- the ctest install_consumers (tests/install/test_install.sh): cmake --install
# into BUILD/install-test/prefix, then a consumer built through pkg-config and through
# find_package(gigatet), and the shared library's exported symbols (only gtet_).  The sanitizer
# builds pass their flags on to the consumer; under TSan it is not registered (the consumer
# would need the TSan runtime and Archer set up as tests/extra-jobs.sh does).
# Included by tests/CMakeLists.txt.
find_program(GTET_BASH bash)
find_program(GTET_PKG_CONFIG pkg-config)
if(GTET_BASH AND NOT GTET_TSAN AND TARGET gigatet_cli)
  set(_gtet_consumer_flags "")
  if(GTET_SANITIZE)
    set(_gtet_consumer_flags "-fsanitize=address,undefined -fno-sanitize-recover=all")
  endif()
  # src/mpi/mpi.cmake is included after tests/: ask at generate time
  set(_gtet_mpi "$<IF:$<TARGET_EXISTS:gigatet_mpi>,1,0>")
  add_test(NAME install_consumers
           COMMAND ${GTET_BASH} ${CMAKE_CURRENT_SOURCE_DIR}/install/test_install.sh
                   ${CMAKE_BINARY_DIR} ${CMAKE_C_COMPILER} ${CMAKE_COMMAND} ${_gtet_mpi}
                   "${_gtet_consumer_flags}")
  set_tests_properties(install_consumers PROPERTIES TIMEOUT 600 LABELS install)
  if(NOT GTET_PKG_CONFIG)
    message(WARNING "gigatet: pkg-config not found; install_consumers will fail (Debian: pkg-config)")
  endif()
endif()
