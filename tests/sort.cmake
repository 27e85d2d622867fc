# sort.cmake -- the sorting benchmark (bench/sort_bench.c): built with the tests so that it
# keeps compiling, never run as a test.  Run: build/tests/sort_bench [runs] [n ...]
add_executable(sort_bench ${CMAKE_CURRENT_SOURCE_DIR}/../bench/sort_bench.c)
target_link_libraries(sort_bench PRIVATE gigatet_static)
