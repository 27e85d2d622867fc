# threads.cmake -- what a run does when the system will not start the threads it asks for
# (NOTES.md E183): an LD_PRELOAD module, gtet_thread_shim (tests/threads/thread_shim.c), that
# stands in for a process limit (pthread_create fails with EAGAIN past a number of live threads,
# or from its K-th call), handed to the CLI's test cli_thread_limits and to the Python module's
# test as GTET_THREAD_SHIM.  Not in sanitizer builds: their runtimes must be loaded first.
# Included by tests/CMakeLists.txt, after cli.cmake and python.cmake (their tests exist).
if(NOT GTET_SANITIZE AND NOT GTET_TSAN AND CMAKE_SYSTEM_NAME STREQUAL "Linux")
  add_library(gtet_thread_shim MODULE ${CMAKE_CURRENT_SOURCE_DIR}/threads/thread_shim.c)
  target_link_libraries(gtet_thread_shim PRIVATE ${CMAKE_DL_LIBS})
  foreach(t cli_thread_limits python_module)
    if(TEST ${t})
      set_property(TEST ${t} APPEND PROPERTY ENVIRONMENT
                   "GTET_THREAD_SHIM=$<TARGET_FILE:gtet_thread_shim>")
    endif()
  endforeach()
endif()
