# sort.cmake -- the sorting benchmark (bench/sort_bench.c): built with the tests so that it
# keeps compiling, never run as a test.  Run: build/tests/sort_bench [runs] [n ...]
add_executable(sort_bench ${CMAKE_CURRENT_SOURCE_DIR}/../bench/sort_bench.c)
target_link_libraries(sort_bench PRIVATE gigatet_static)

# The Moore state tables are generated: the committed header must be what the generator
# prints (the generator also re-verifies the curve on 2^1..2^4 grids before printing).
find_program(GTET_PYTHON3 python3)
if(GTET_PYTHON3)
  add_test(NAME test_sort_moore_table_is_generated
           COMMAND sh -c "\"${GTET_PYTHON3}\" \"$0/gen_moore_table.py\" | cmp - \"$0/moore_table.h\""
                   ${CMAKE_CURRENT_SOURCE_DIR}/../src/sort)
  set_tests_properties(test_sort_moore_table_is_generated PROPERTIES TIMEOUT 120)
endif()
