# check.cmake -- test rules of the oracle / checker area (included by tests/CMakeLists.txt).
#
# test_oracle_cgal (C++): the oracle's perturbation against CGAL's Delaunay_triangulation_3, and
# CGAL's meshes through the exact checker.  Built when GTET_CGAL_TESTS is on and a C++ compiler
# and CGAL's headers are found.  GCC 12 rejects -fexcess-precision=standard for C++ (the project
# adds it for every language), so that one flag is dropped from this C++ target; the others
# (-ffp-contract=off, -frounding-math, ...) stay.
if(GTET_CGAL_TESTS)
  include(CheckLanguage)
  check_language(CXX)
  find_path(GTET_CGAL_INCLUDE_DIR CGAL/Delaunay_triangulation_3.h)
  if(CMAKE_CXX_COMPILER AND GTET_CGAL_INCLUDE_DIR AND MPFR_LIBRARY)
    enable_language(CXX)
    add_executable(test_oracle_cgal ${CMAKE_CURRENT_SOURCE_DIR}/test_oracle_cgal.cpp)
    set_target_properties(test_oracle_cgal PROPERTIES CXX_STANDARD 17 CXX_STANDARD_REQUIRED ON)
    get_target_property(_gtet_opts test_oracle_cgal COMPILE_OPTIONS)
    if(_gtet_opts)
      list(FILTER _gtet_opts EXCLUDE REGEX "excess-precision")
      set_target_properties(test_oracle_cgal PROPERTIES COMPILE_OPTIONS "${_gtet_opts}")
    endif()
    target_include_directories(test_oracle_cgal PRIVATE ${GTET_CGAL_INCLUDE_DIR})
    target_link_libraries(test_oracle_cgal PRIVATE gigatet_static ${MPFR_LIBRARY} ${GMP_LIBRARY})
    add_test(NAME test_oracle_cgal COMMAND test_oracle_cgal)
    set_tests_properties(test_oracle_cgal PROPERTIES TIMEOUT 600)
  endif()
endif()
