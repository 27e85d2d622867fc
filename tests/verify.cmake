# verify.cmake -- rules of the verification layer's tests (issue 5 and issue 4's race job).
#
# Under GTET_TSAN only: tests/parallel_race_canary.c, a deliberately racy OpenMP loop, is the
# ctest tsan_flags_a_deliberate_data_race; it passes only when ThreadSanitizer prints a data
# race report for it (PASS_REGULAR_EXPRESSION: the exit code is ignored), so the TSan job in
# tests/extra-jobs.sh fails when TSan/Archer are not really watching.  The canary is not a
# test_*.c: in other builds it would prove nothing.
if(GTET_TSAN)
  add_executable(parallel_race_canary ${CMAKE_CURRENT_SOURCE_DIR}/parallel_race_canary.c)
  target_link_libraries(parallel_race_canary PRIVATE OpenMP::OpenMP_C)
  add_test(NAME tsan_flags_a_deliberate_data_race COMMAND parallel_race_canary)
  set_tests_properties(tsan_flags_a_deliberate_data_race PROPERTIES
                       PASS_REGULAR_EXPRESSION "WARNING: ThreadSanitizer: data race"
                       LABELS "tsan" TIMEOUT 120)
endif()
