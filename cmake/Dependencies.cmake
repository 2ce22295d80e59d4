# Finds the Debian-packaged dependencies and says exactly what to install when one is missing.
set(_granflow_missing "")

find_package(Eigen3 3.3 QUIET NO_MODULE)
if(NOT TARGET Eigen3::Eigen)
  list(APPEND _granflow_missing libeigen3-dev)
endif()

# The library links HDF5::HDF5 (FindHDF5's imported target: the C library, its include
# directory as a system one), the name the installed package's config finds it by again.
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

# OpenMP: the engine's optional threads (SolverSettings::threads, default 1). GCC's
# runtime is libgomp; Clang's is libomp.
find_package(OpenMP QUIET COMPONENTS CXX)
if(NOT OpenMP_CXX_FOUND)
  if(CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    list(APPEND _granflow_missing libomp-dev)
  else()
    list(APPEND _granflow_missing libgomp1)
  endif()
endif()

# help2man makes each program's man page from its --help and --version (cmake/Install.cmake).
find_program(GRANFLOW_HELP2MAN help2man)
if(NOT GRANFLOW_HELP2MAN)
  list(APPEND _granflow_missing help2man)
endif()

if(GRANFLOW_TESTS)
  find_package(GTest QUIET)
  if(NOT GTest_FOUND)
    list(APPEND _granflow_missing libgtest-dev)
  endif()
  # The Python tests (analysis and figure scripts, the docs check) run with this interpreter
  # (Python3_EXECUTABLE). The first python3 on PATH may lack the modules the scripts import
  # (a pyenv or virtualenv one): without -DPython3_EXECUTABLE=..., take the first python3
  # on PATH that has them, else the first one, which then names the packages to install.
  set(_granflow_python_modules numpy h5py matplotlib)
  if(NOT Python3_EXECUTABLE AND CMAKE_VERSION VERSION_GREATER_EQUAL 3.25)
    function(_granflow_python_has_modules result candidate)
      list(JOIN _granflow_python_modules ", " _imports)
      execute_process(COMMAND ${candidate} -c "import ${_imports}"
                      RESULT_VARIABLE _rc OUTPUT_QUIET ERROR_QUIET)
      if(NOT _rc EQUAL 0)
        set(${result} FALSE PARENT_SCOPE)
      endif()
    endfunction()
    find_program(GRANFLOW_PYTHON3 NAMES python3 VALIDATOR _granflow_python_has_modules NO_CACHE)
    if(GRANFLOW_PYTHON3)
      set(Python3_EXECUTABLE ${GRANFLOW_PYTHON3} CACHE FILEPATH "Python 3 interpreter of the Python tests")
    endif()
  endif()
  find_package(Python3 QUIET COMPONENTS Interpreter)
  if(NOT Python3_Interpreter_FOUND)
    list(APPEND _granflow_missing python3)
  else()
    foreach(_module ${_granflow_python_modules})
      execute_process(COMMAND ${Python3_EXECUTABLE} -c "import ${_module}"
                      RESULT_VARIABLE _rc OUTPUT_QUIET ERROR_QUIET)
      if(NOT _rc EQUAL 0)
        list(APPEND _granflow_missing python3-${_module})
      endif()
    endforeach()
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
