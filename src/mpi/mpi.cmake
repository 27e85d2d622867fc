# gigatet's distributed mode over MPI (src/mpi/): libgigatet_mpi, the gigatet-mpi tool and
# the MPI tests (tests/mpi/).  Included by one line at the end of the root CMakeLists.txt;
# everything MPI lives here.
find_package(MPI COMPONENTS C QUIET)
set(_gtet_mpi_default OFF)
if(MPI_C_FOUND)
  set(_gtet_mpi_default ON)
endif()
option(GTET_MPI "Build the distributed mode over MPI (gigatet_mpi.h, gigatet-mpi)" ${_gtet_mpi_default})
if(NOT GTET_MPI)
  return()
endif()
if(NOT MPI_C_FOUND)
  message(FATAL_ERROR "GTET_MPI=ON but no MPI C library was found (Debian: libopenmpi-dev)")
endif()

set(_gtet_mpi_dir ${CMAKE_CURRENT_LIST_DIR})
add_library(gigatet_mpi STATIC ${_gtet_mpi_dir}/mpi_util.c ${_gtet_mpi_dir}/mpi_pages.c ${_gtet_mpi_dir}/mpi_ids.c
            ${_gtet_mpi_dir}/mpi_partition.c ${_gtet_mpi_dir}/mpi_query.c ${_gtet_mpi_dir}/mpi_lift.c ${_gtet_mpi_dir}/mpi_far.c ${_gtet_mpi_dir}/mpi_ghosts.c ${_gtet_mpi_dir}/mpi_patch.c ${_gtet_mpi_dir}/mpi_cavity.c
            ${_gtet_mpi_dir}/mpi_output.c ${_gtet_mpi_dir}/mpi_triangulate.c ${_gtet_mpi_dir}/mpi_check.c)
target_include_directories(gigatet_mpi PUBLIC ${_gtet_mpi_dir} ${GTET_INCLUDE_DIRS})
target_link_libraries(gigatet_mpi PUBLIC gigatet_static MPI::MPI_C ${M_LIBRARY})

add_executable(gigatet_mpi_cli ${_gtet_mpi_dir}/cli_mpi.c)
set_target_properties(gigatet_mpi_cli PROPERTIES OUTPUT_NAME gigatet-mpi)
target_link_libraries(gigatet_mpi_cli PRIVATE gigatet_mpi gigatet_io)

if(BUILD_TESTING AND EXISTS ${PROJECT_SOURCE_DIR}/tests/mpi/run_tests.sh)
  find_program(GTET_MPIEXEC NAMES mpirun mpiexec)
  if(GTET_MPIEXEC)
    foreach(_t IN ITEMS equal degenerate io bad_input api)
      add_test(NAME mpi_${_t}
               COMMAND ${PROJECT_SOURCE_DIR}/tests/mpi/run_tests.sh ${_t}
                       $<TARGET_FILE:gigatet_mpi_cli> $<TARGET_FILE:gigatet_cli>
                       ${PROJECT_BINARY_DIR}/mpi-tests ${GTET_MPIEXEC}
                       $<TARGET_FILE:test_mpi_api>)
      set_tests_properties(mpi_${_t} PROPERTIES TIMEOUT 300 LABELS mpi)
      if(GTET_SANITIZE)
        # Open MPI's plugins are unloaded at exit with allocations LeakSanitizer reports from
        # unknown modules (no suppression can name them); ASan's memory errors and UBSan stay
        # on, and gigatet's own leaks are caught by the non-MPI tests
        set_tests_properties(mpi_${_t} PROPERTIES ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")
      endif()
    endforeach()
  endif()
  add_executable(test_mpi_api ${PROJECT_SOURCE_DIR}/tests/mpi/test_mpi_api.c)
  target_link_libraries(test_mpi_api PRIVATE gigatet_mpi)
endif()
