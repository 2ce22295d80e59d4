# What `cmake --install <build> --prefix P` installs (docs/install.md):
#   P/bin                          the programs
#   P/lib                          libgranflow.a and libgranflow_statistics.so
#   P/include/granflow/<folder>/   the headers of lib/, by folder; included as "io/trajectory.hpp"
#   P/lib/cmake/granflow           the CMake package: granflow::granflow, granflow::statistics
#   P/lib/pkgconfig/granflow.pc    the same library for pkg-config
#   P/share/man/man1               a man page per program, made by help2man from its --help
#   P/lib/python3/dist-packages    the Python package granflow with its statistics library
# (lib, include and share/man as GNUInstallDirs names them: CMAKE_INSTALL_LIBDIR and so on.)
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

# ---------------------------------------------------------------- man pages
# help2man reads `<program> --help` and `--version` (pages built with `all`) through
# cmake/man/help2man-view.sh, which lays the options out as help2man expects and adds a
# section per command of gf-stz; the NAME line comes from _man_names, and a SEE ALSO section
# names the other programs.
set(_man_dir ${PROJECT_BINARY_DIR}/man/man1)
set(_man_names
    "gf-pack=biperiodic packings of polydisperse disks at an exact packing fraction, and incline starts"
    "gf-shear=Lees-Edwards simple shear of rigid disks by Contact Dynamics"
    "gf-incline=flow of rigid disks down a rough incline, and its depth profiles"
    "gf-correlate=force correlations, correlation lengths, force distributions and contact clusters"
    "gf-network=the force network: long-lived coordination, deflections, fabric and its relations"
    "gf-kinetic=kinetic theory against shear runs: chi, Enskog predictions, velocity correlations"
    "gf-stz=non-affine motion (D2min) and the STZ law fitted to shear runs"
    "gf-xdmf=an XDMF description of a trajectory for ParaView")
set(_man_pages "")
foreach(program ${_granflow_programs})
  set(_name "")
  foreach(entry ${_man_names})
    if(entry MATCHES "^${program}=(.*)$")
      set(_name "${CMAKE_MATCH_1}")
    endif()
  endforeach()
  if(_name STREQUAL "")
    message(FATAL_ERROR "cmake/Install.cmake: no NAME line for ${program}'s man page in _man_names")
  endif()
  # SEE ALSO (a help2man include file): the other programs, and where the full reference is.
  # Written only when it changes (file(CONFIGURE)), so that a new configure remakes no page.
  set(_others "")
  foreach(other ${_granflow_programs})
    if(NOT other STREQUAL program)
      list(APPEND _others ".BR ${other} (1)")
    endif()
  endforeach()
  list(JOIN _others ",\n" _see_also)
  string(PREPEND _see_also "[SEE ALSO]\n")
  string(APPEND _see_also "\n.PP\nEvery option with its inputs, outputs and examples: docs/programs/${program}.md "
                          "in granflow's source; the files: docs/file-format.md.\n")
  string(REPLACE "-" "\\-" _see_also "${_see_also}")  # roff: a minus sign, not a hyphen
  file(CONFIGURE OUTPUT ${PROJECT_BINARY_DIR}/man/${program}.h2m CONTENT "${_see_also}" @ONLY)
  add_custom_command(
    OUTPUT ${_man_dir}/${program}.1
    COMMAND ${CMAKE_COMMAND} -E make_directory ${_man_dir}
    COMMAND ${CMAKE_COMMAND} -E env GRANFLOW_PROGRAM=$<TARGET_FILE:${program}>
            ${GRANFLOW_HELP2MAN} --no-info --locale=C.UTF-8 --section=1 --name=${_name}
            --include=${PROJECT_BINARY_DIR}/man/${program}.h2m --output=${_man_dir}/${program}.1
            ${PROJECT_SOURCE_DIR}/cmake/man/help2man-view.sh
    DEPENDS ${program} ${PROJECT_BINARY_DIR}/man/${program}.h2m ${PROJECT_SOURCE_DIR}/cmake/man/help2man-view.sh
    COMMENT "Man page of ${program} (help2man)"
    VERBATIM)
  list(APPEND _man_pages ${_man_dir}/${program}.1)
endforeach()
add_custom_target(granflow_man_pages ALL DEPENDS ${_man_pages})
install(FILES ${_man_pages} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)

# ---------------------------------------------------------------- Python package
# The package granflow (python/granflow, docs/python.md) with the statistics library it loads
# beside its modules, as `pip install ./python` lays it out, under GRANFLOW_INSTALL_PYTHONDIR
# (default lib/python3/dist-packages: on Debian's python3 path when P is /usr/local).
set(GRANFLOW_INSTALL_PYTHONDIR lib/python3/dist-packages CACHE STRING
    "where cmake --install puts the Python package granflow, relative to the prefix")
install(DIRECTORY ${PROJECT_SOURCE_DIR}/python/granflow DESTINATION ${GRANFLOW_INSTALL_PYTHONDIR}
        FILES_MATCHING PATTERN "*.py" PATTERN "__pycache__" EXCLUDE)
install(FILES $<TARGET_FILE:granflow_statistics> DESTINATION ${GRANFLOW_INSTALL_PYTHONDIR}/granflow)
