# tests/cgal.cmake -- the differential tests against CGAL (tests/cgal/).
#
# Built only with GTET_CGAL_TESTS=ON, a C++ compiler, CGAL and python3; otherwise a status
# line says what is missing and nothing here is compiled.  The root project is C only, so C++
# is enabled here.  Programs:
#   cgal_dt  CGAL's Delaunay_triangulation_3 (Epick; TBB parallel mode when TBB is found)
#   gtet_dt  gigatet through its public header, same canonical output (tests/canon.h)
# Tests (label "cgal"; under GTET_SANITIZE they use the small point sets, label "sanitize"):
#   cgal_reference_is_independent_of_order_and_threads    CGAL vs CGAL (validates the driver)
#   gigatet_tets_equal_cgal_on_random_points              \
#   gigatet_tets_equal_cgal_on_degenerate_sets             } gigatet vs CGAL, plain, -t 2,
#   gigatet_tets_equal_cgal_on_extreme_scales_and_duplicates / and on shuffled input

if(NOT GTET_CGAL_TESTS)
  return()
endif()

include(CheckLanguage)
check_language(CXX)
if(NOT CMAKE_CXX_COMPILER)
  message(STATUS "gigatet: no C++ compiler; CGAL differential tests skipped")
  return()
endif()
enable_language(CXX)
find_package(CGAL QUIET)
find_package(Python3 QUIET COMPONENTS Interpreter)
if(NOT CGAL_FOUND OR NOT Python3_Interpreter_FOUND)
  message(STATUS "gigatet: CGAL (${CGAL_FOUND}) or python3 (${Python3_Interpreter_FOUND}) "
                 "missing; CGAL differential tests skipped")
  return()
endif()
find_package(TBB QUIET)
# By path: a second find_package(CGAL) in another directory returns early, without
# adding CGAL's module directory to CMAKE_MODULE_PATH.
find_file(GTET_CGAL_TBB_SUPPORT CGAL_TBB_support.cmake HINTS ${CGAL_MODULES_DIR} ${CGAL_DIR}
          NO_DEFAULT_PATH)
if(TBB_FOUND AND GTET_CGAL_TBB_SUPPORT AND NOT TARGET CGAL::TBB_support)
  include(${GTET_CGAL_TBB_SUPPORT})
endif()

set(GTET_CGAL_DIR ${CMAKE_CURRENT_LIST_DIR}/cgal)

# The project-wide FP flags are right for C++ too, except -fexcess-precision=standard, which
# g++ < 13 rejects for C++ (SSE2 doubles have no excess precision anyway: FLT_EVAL_METHOD 0 is
# checked at configure time).
function(gtet_cxx_fix_flags target)
  get_target_property(opts ${target} COMPILE_OPTIONS)
  if(opts)
    list(REMOVE_ITEM opts -fexcess-precision=standard)
    set_target_properties(${target} PROPERTIES COMPILE_OPTIONS "${opts}")
  endif()
endfunction()

add_executable(cgal_dt ${GTET_CGAL_DIR}/cgal_dt.cpp)
set_target_properties(cgal_dt PROPERTIES CXX_STANDARD 17 CXX_STANDARD_REQUIRED ON
                                         CXX_EXTENSIONS OFF)
target_link_libraries(cgal_dt PRIVATE CGAL::CGAL)
if(TARGET CGAL::TBB_support)
  target_link_libraries(cgal_dt PRIVATE CGAL::TBB_support)
else()
  message(STATUS "gigatet: TBB not found; cgal_dt has no parallel mode")
endif()
gtet_cxx_fix_flags(cgal_dt)

if(GTET_SANITIZE)
  set(_small --small)
  set(_labels "cgal;sanitize")
else()
  set(_small "")
  set(_labels "cgal")
endif()
set(_driver ${Python3_EXECUTABLE} ${GTET_CGAL_DIR}/compare.py --cgal $<TARGET_FILE:cgal_dt>
    ${_small})

# CGAL against itself (parallel, shuffled) validates the driver and the reference; the small
# sizes suffice for that, the gigatet comparisons below use the full ones.
if(GTET_SANITIZE)
  add_test(NAME cgal_reference_is_independent_of_order_and_threads COMMAND ${_driver})
else()
  add_test(NAME cgal_reference_is_independent_of_order_and_threads COMMAND ${_driver} --small)
endif()
set_tests_properties(cgal_reference_is_independent_of_order_and_threads PROPERTIES
                     LABELS "${_labels}" TIMEOUT 900)

add_executable(gtet_dt ${GTET_CGAL_DIR}/gtet_dt.c)
target_link_libraries(gtet_dt PRIVATE gigatet_static)
set(_fam_random "uniform_1k,uniform_10k,uniform_100k,uniform_with_duplicates")
set(_fam_degenerate "grid_10,grid_20_duplicates,cospherical_r2_2025,cospherical_r2_21125_centre,cube_corners,cube_corners_centre,fcc,bcc,paraboloid,plane_apex,plane_denormal_apex")
set(_fam_extreme "uniform_tiny_2m1000,uniform_huge_2p1000,grid_huge_2p1000,mixed_scales,signed_zeros_duplicates")
foreach(kind random degenerate extreme)
  if(kind STREQUAL "random")
    set(_name gigatet_tets_equal_cgal_on_random_points)
  elseif(kind STREQUAL "degenerate")
    set(_name gigatet_tets_equal_cgal_on_degenerate_sets)
  else()
    set(_name gigatet_tets_equal_cgal_on_extreme_scales_and_duplicates)
  endif()
  add_test(NAME ${_name} COMMAND ${_driver} --gtet $<TARGET_FILE:gtet_dt> --skip-cgal-self
                                 --families ${_fam_${kind}})
  set_tests_properties(${_name} PROPERTIES LABELS "${_labels}" TIMEOUT 900)
endforeach()

# CGAL's meshes of a grid and a co-spherical set through `gigatet check` (canonical and
# --delaunay) and `gigatet diff` (identical to gigatet's; TetGen's grid mesh: ties).
if(TARGET gigatet_cli)
  find_program(GTET_BASH bash)
  add_test(NAME check_and_diff_accept_cgal_meshes
           COMMAND ${GTET_BASH} ${GTET_CGAL_DIR}/check_diff_cgal.sh $<TARGET_FILE:gigatet_cli>
                   $<TARGET_FILE:cgal_dt>)
  set_tests_properties(check_and_diff_accept_cgal_meshes PROPERTIES LABELS "${_labels}" TIMEOUT 300)
endif()
