# Finds the Debian-packaged dependencies and says exactly what to install when one is missing.
set(_granflow_missing "")

find_package(Eigen3 3.3 QUIET NO_MODULE)
if(NOT TARGET Eigen3::Eigen)
  list(APPEND _granflow_missing libeigen3-dev)
endif()

find_package(HDF5 QUIET COMPONENTS C)
if(NOT HDF5_FOUND)
  list(APPEND _granflow_missing libhdf5-dev)
endif()

find_package(GSL QUIET)
if(NOT GSL_FOUND)
  list(APPEND _granflow_missing libgsl-dev)
endif()

find_package(PkgConfig QUIET)
if(PkgConfig_FOUND)
  pkg_check_modules(FFTW3 QUIET IMPORTED_TARGET fftw3)
endif()
if(NOT FFTW3_FOUND)
  list(APPEND _granflow_missing libfftw3-dev)
  if(NOT PkgConfig_FOUND)
    list(APPEND _granflow_missing pkg-config)
  endif()
endif()

if(GRANFLOW_TESTS)
  find_package(GTest QUIET)
  if(NOT GTest_FOUND)
    list(APPEND _granflow_missing libgtest-dev)
  endif()
endif()
if(GRANFLOW_BENCH)
  find_package(benchmark QUIET)
  if(NOT benchmark_FOUND)
    list(APPEND _granflow_missing libbenchmark-dev)
  endif()
endif()

if(_granflow_missing)
  list(JOIN _granflow_missing " " _pkgs)
  message(FATAL_ERROR
    "granflow: missing build dependencies: ${_pkgs}\n"
    "Install them with:  sudo apt-get install -y ${_pkgs}\n"
    "(or run 'make -f Makefile.sweeps deps', which does it for you as root).")
endif()

add_library(granflow_hdf5 INTERFACE)
target_include_directories(granflow_hdf5 SYSTEM INTERFACE ${HDF5_INCLUDE_DIRS})
target_link_libraries(granflow_hdf5 INTERFACE ${HDF5_C_LIBRARIES})
target_compile_definitions(granflow_hdf5 INTERFACE ${HDF5_DEFINITIONS})
