# tests/pred.cmake -- special rules of the predicate tests (included by tests/CMakeLists.txt).
#
# 1. test_fp_contraction_is_detected: the predicate sources and test_fp_assumptions.c compiled
#    a second time WITH -ffp-contract=fast -mfma; pred_fp_selftest() must then report the
#    contraction, so the test program fails: registered WILL_FAIL (the suite proves the
#    check can fail).  Needs a CPU with FMA (x86-64-v3); elsewhere the test is not added.
# 2. test_fpenv_rejects_fast_math: compiling a predicate source with -ffast-math must fail
#    (fpenv.h #error), WILL_FAIL; test_fpenv_accepts_default_flags is the control (same
#    command without -ffast-math must succeed).
# 3. pred_stage_counts: the stage-count / timing program for NOTES.md, plus a quick ctest.
# 4. test_pred_packed_filter_avx2 compiled with -mavx2 (at the end).
set(GTET_PRED_SRC_DIR ${PROJECT_SOURCE_DIR}/src/pred)
file(GLOB GTET_PRED_SOURCES CONFIGURE_DEPENDS ${GTET_PRED_SRC_DIR}/*.c)

include(CheckCSourceRuns)
set(CMAKE_REQUIRED_FLAGS "-mfma")
check_c_source_runs("
#include <immintrin.h>
int main(void){ return __builtin_cpu_supports(\"fma\") ? 0 : 1; }" GTET_CPU_HAS_FMA)
unset(CMAKE_REQUIRED_FLAGS)

if(GTET_CPU_HAS_FMA AND CMAKE_C_COMPILER_ID MATCHES "GNU|Clang")
  add_executable(test_fp_contraction_is_detected
                 ${CMAKE_CURRENT_SOURCE_DIR}/test_fp_assumptions.c
                 ${CMAKE_CURRENT_SOURCE_DIR}/testutil.c ${GTET_PRED_SOURCES})
  target_include_directories(test_fp_contraction_is_detected PRIVATE
                             ${GTET_INCLUDE_DIRS} ${CMAKE_CURRENT_SOURCE_DIR} ${GMP_INCLUDE_DIR})
  # Replace (not append to) the project-wide options: clang ignores a later
  # -ffp-contract=fast after -fno-unsafe-math-optimizations / under -frounding-math.
  # -O2 in every build type: GCC contracts only when optimizing.
  set_property(TARGET test_fp_contraction_is_detected PROPERTY COMPILE_OPTIONS
               -O2 -ffp-contract=fast -mfma)
  target_link_libraries(test_fp_contraction_is_detected PRIVATE ${GMP_LIBRARY} ${M_LIBRARY})
  add_test(NAME test_fp_contraction_is_detected COMMAND test_fp_contraction_is_detected)
  set_tests_properties(test_fp_contraction_is_detected PROPERTIES WILL_FAIL TRUE TIMEOUT 60)
endif()

add_test(NAME test_fpenv_accepts_default_flags
         COMMAND ${CMAKE_C_COMPILER} -std=c17 -fsyntax-only -I${PROJECT_SOURCE_DIR}/include
                 -I${PROJECT_SOURCE_DIR}/src
                 ${GTET_PRED_SRC_DIR}/fpcheck.c)
add_test(NAME test_fpenv_rejects_fast_math
         COMMAND ${CMAKE_C_COMPILER} -std=c17 -ffast-math -fsyntax-only
                 -I${PROJECT_SOURCE_DIR}/include -I${PROJECT_SOURCE_DIR}/src
                 ${GTET_PRED_SRC_DIR}/fpcheck.c)
set_tests_properties(test_fpenv_rejects_fast_math PROPERTIES WILL_FAIL TRUE TIMEOUT 60)
set_tests_properties(test_fpenv_accepts_default_flags PROPERTIES TIMEOUT 60)

add_executable(pred_stage_counts ${CMAKE_CURRENT_SOURCE_DIR}/pred_stage_counts.c)
target_link_libraries(pred_stage_counts PRIVATE gtet_testutil gigatet_static)
add_test(NAME test_pred_stage_counts_are_consistent COMMAND pred_stage_counts --quick)
set_tests_properties(test_pred_stage_counts_are_consistent PROPERTIES TIMEOUT 300)

# 4. test_pred_packed_filter_avx2: test_pred_packed_filter.c compiled with -mavx2, where the
#    packed filters take four lanes (filter_packed.h pred_insphere_lanes4_, run by
#    src/kernel/insert_avx2.c); only where the library builds that unit (GTET_AVX2_TU).
if(GTET_AVX2_TU AND TARGET test_pred_packed_filter_avx2)
  target_compile_options(test_pred_packed_filter_avx2 PRIVATE -mavx2)
endif()
