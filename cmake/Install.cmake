# What `cmake --install <build> --prefix P` installs (docs/install.md):
#   P/bin                          the programs
#   P/lib                          libgranflow.a and libgranflow_statistics.so
#   P/include/granflow/<folder>/   the headers of lib/, by folder; included as "io/trajectory.hpp"
#   P/lib/cmake/granflow           the CMake package: granflow::granflow, granflow::statistics
#   P/lib/pkgconfig/granflow.pc    the same library for pkg-config
# (lib and include as GNUInstallDirs names them: CMAKE_INSTALL_LIBDIR and so on.)
include(CMakePackageConfigHelpers)

set(GRANFLOW_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/granflow)
file(GLOB _granflow_program_sources CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tools/gf-*.cpp)
set(_granflow_programs "")
foreach(src ${_granflow_program_sources})
  get_filename_component(name ${src} NAME_WE)
  list(APPEND _granflow_programs ${name})
endforeach()

# ---------------------------------------------------------------- programs and libraries
# The programs as built, byte for byte (their build RPATH names only the system directories of
# the shared libraries they link, e.g. HDF5's, never the build tree): install(TARGETS) would
# make the linker pad that RPATH for rewriting at install time, changing every program's file
# and so its content-hash stamp (pipelines/update-stamps.sh), which would remake every run.
foreach(program ${_granflow_programs})
  install(PROGRAMS $<TARGET_FILE:${program}> DESTINATION ${CMAKE_INSTALL_BINDIR})
endforeach()

set_target_properties(granflow_statistics PROPERTIES EXPORT_NAME statistics)
install(TARGETS granflow granflow_statistics EXPORT granflowTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
# Every header of lib/ in its folder (lib/io/trajectory.hpp as include/granflow/io/trajectory.hpp),
# so that the installed headers include each other as they do in the source tree.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/lib/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/granflow
        FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h")

# ---------------------------------------------------------------- CMake package
install(EXPORT granflowTargets NAMESPACE granflow:: DESTINATION ${GRANFLOW_CMAKE_DIR})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/granflowConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/package/granflowConfig.cmake
                              INSTALL_DESTINATION ${GRANFLOW_CMAKE_DIR})
# Any 0.1.x satisfies find_package(granflow 0.1): the interface may change between minor versions.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/package/granflowConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/package/granflowConfig.cmake
              ${PROJECT_BINARY_DIR}/package/granflowConfigVersion.cmake
        DESTINATION ${GRANFLOW_CMAKE_DIR})

# ---------------------------------------------------------------- pkg-config
# Paths relative to the .pc file's own place (${pcfiledir}), so that the file is right under
# any prefix given to `cmake --install --prefix`, not only CMAKE_INSTALL_PREFIX.
set(_pc_dir ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
if(IS_ABSOLUTE ${CMAKE_INSTALL_LIBDIR} OR IS_ABSOLUTE ${CMAKE_INSTALL_INCLUDEDIR})
  set(GRANFLOW_PC_PREFIX ${CMAKE_INSTALL_PREFIX})
else()
  file(RELATIVE_PATH _up /root/${_pc_dir} /root)
  string(REGEX REPLACE "/$" "" _up "${_up}")
  set(GRANFLOW_PC_PREFIX "\${pcfiledir}/${_up}")
endif()
foreach(dir LIBDIR INCLUDEDIR)
  if(IS_ABSOLUTE ${CMAKE_INSTALL_${dir}})
    set(GRANFLOW_PC_${dir} ${CMAKE_INSTALL_${dir}})
  else()
    set(GRANFLOW_PC_${dir} "\${prefix}/${CMAKE_INSTALL_${dir}}")
  endif()
endforeach()
configure_file(${PROJECT_SOURCE_DIR}/cmake/granflow.pc.in ${PROJECT_BINARY_DIR}/package/granflow.pc @ONLY)
install(FILES ${PROJECT_BINARY_DIR}/package/granflow.pc DESTINATION ${_pc_dir})

# PYTHON PACKAGE (pipelines/granflow_py): its install rules go here (issue 46); not installed yet.
