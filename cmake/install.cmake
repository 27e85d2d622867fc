# cmake/install.cmake -- what `cmake --install build --prefix P` puts under P (README "Install"):
#   include/gigatet.h (+ gigatet_mpi.h with GTET_MPI), lib*/libgigatet.so.MAJOR (SONAME) and
#   libgigatet.a, bin/gigatet (+ gigatet-mpi), lib*/pkgconfig/gigatet.pc,
#   lib*/cmake/gigatet/ (find_package(gigatet) -> gigatet::gigatet, the shared library, and
#   gigatet::gigatet_static), share/man/man1/gigatet.1.
# Included by one line at the end of the root CMakeLists.txt (after src/mpi/mpi.cmake).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

# the header's version macros and project() must agree (gtet_version() prints the former)
file(STRINGS ${PROJECT_SOURCE_DIR}/include/gigatet.h _gtet_ver REGEX "^#define GTET_VERSION_(MAJOR|MINOR|PATCH) ")
string(REGEX REPLACE "[^;]*MAJOR ([0-9]+);[^;]*MINOR ([0-9]+);[^;]*PATCH ([0-9]+)" "\\1.\\2.\\3"
       _gtet_ver "${_gtet_ver}")
if(NOT _gtet_ver STREQUAL PROJECT_VERSION)
  message(FATAL_ERROR "include/gigatet.h says version ${_gtet_ver}, CMakeLists.txt ${PROJECT_VERSION}")
endif()

set(GTET_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/gigatet)

install(FILES ${PROJECT_SOURCE_DIR}/include/gigatet.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT devel)
install(TARGETS gigatet_shared EXPORT gigatetTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT runtime NAMELINK_COMPONENT devel)
install(TARGETS gigatet_static EXPORT gigatetTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT devel)
if(TARGET gigatet_cli)
  install(TARGETS gigatet_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
  install(FILES ${PROJECT_SOURCE_DIR}/doc/gigatet.1
          DESTINATION ${CMAKE_INSTALL_MANDIR}/man1 COMPONENT runtime)
endif()
if(TARGET gigatet_mpi)
  # the distributed mode: its header, its static library (link -lgigatet_mpi -lgigatet and
  # MPI's C library, gigatet_mpi.h) and the tool
  install(FILES ${PROJECT_SOURCE_DIR}/include/gigatet_mpi.h
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} COMPONENT devel)
  install(TARGETS gigatet_mpi ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT devel)
endif()
if(TARGET gigatet_mpi_cli)
  install(TARGETS gigatet_mpi_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
endif()

# ---- CMake package
install(EXPORT gigatetTargets NAMESPACE gigatet:: DESTINATION ${GTET_INSTALL_CMAKEDIR}
        COMPONENT devel)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/gigatetConfig.cmake.in
  ${PROJECT_BINARY_DIR}/gigatetConfig.cmake INSTALL_DESTINATION ${GTET_INSTALL_CMAKEDIR})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/gigatetConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
install(FILES ${PROJECT_BINARY_DIR}/gigatetConfig.cmake ${PROJECT_BINARY_DIR}/gigatetConfigVersion.cmake
        DESTINATION ${GTET_INSTALL_CMAKEDIR} COMPONENT devel)

# ---- pkg-config: `pkg-config --cflags --libs gigatet` (shared), add --static for libgigatet.a
# relocatable: the prefix is found from the .pc file's own place (--prefix is chosen at install
# time, after configure), unless the install directories are absolute
set(GTET_PC_OPENMP_FLAGS "${OpenMP_C_FLAGS}")
file(RELATIVE_PATH _gtet_pc_up /_p/${CMAKE_INSTALL_LIBDIR}/pkgconfig /_p)
string(REGEX REPLACE "/$" "" _gtet_pc_up "${_gtet_pc_up}")
set(GTET_PC_PREFIX "\${pcfiledir}/${_gtet_pc_up}")
foreach(_d LIBDIR INCLUDEDIR)
  if(IS_ABSOLUTE "${CMAKE_INSTALL_${_d}}")
    set(GTET_PC_${_d} "${CMAKE_INSTALL_${_d}}")
  else()
    set(GTET_PC_${_d} "\${prefix}/${CMAKE_INSTALL_${_d}}")
  endif()
endforeach()
configure_file(${PROJECT_SOURCE_DIR}/cmake/gigatet.pc.in ${PROJECT_BINARY_DIR}/gigatet.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/gigatet.pc
        DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig COMPONENT devel)
