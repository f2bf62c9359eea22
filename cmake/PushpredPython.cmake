# Finds the Python interpreter and pybind11 for the Python module; sets PUSHPRED_PYTHON_ENABLED.
#
# The interpreter must import numpy (the module's arrays are numpy arrays, and its tests need numpy and pytest).
# The first python3 on PATH may be another installation without Debian's python3-numpy (a pyenv shim, a venv):
# unless Python3_EXECUTABLE is given, the python3 programs on PATH are tried in order, then the system's, and the
# first that imports numpy is used.
if(NOT Python3_EXECUTABLE)
  set(candidates)
  string(REPLACE ":" ";" path_entries "$ENV{PATH}")
  foreach(dir ${path_entries} /usr/bin)
    if(EXISTS ${dir}/python3 AND NOT IS_DIRECTORY ${dir}/python3)
      list(APPEND candidates ${dir}/python3)
    endif()
  endforeach()
  list(REMOVE_DUPLICATES candidates)
  foreach(candidate ${candidates})
    execute_process(COMMAND ${candidate} -c "import numpy" RESULT_VARIABLE numpy_missing OUTPUT_QUIET ERROR_QUIET)
    if(numpy_missing EQUAL 0)
      set(Python3_EXECUTABLE ${candidate} CACHE FILEPATH "Python interpreter for the pushpred module")
      break()
    endif()
  endforeach()
endif()
if(NOT Python3_EXECUTABLE)
  message(STATUS "pushpred Python module: skipped, no python3 that imports numpy (apt-get install python3-numpy)")
  return()
endif()

find_package(Python3 3.9 COMPONENTS Interpreter Development.Module)
if(NOT Python3_FOUND)
  message(STATUS "pushpred Python module: skipped, Python 3 headers not found (apt-get install python3-dev)")
  return()
endif()
find_package(pybind11 2.6 CONFIG QUIET)
if(NOT pybind11_FOUND)
  message(STATUS "pushpred Python module: skipped, pybind11 not found (apt-get install pybind11-dev)")
  return()
endif()
execute_process(COMMAND ${Python3_EXECUTABLE} -c "import pytest" RESULT_VARIABLE pytest_missing
                OUTPUT_QUIET ERROR_QUIET)
set(PUSHPRED_PYTEST_FOUND OFF)
if(pytest_missing EQUAL 0)
  set(PUSHPRED_PYTEST_FOUND ON)
endif()
message(STATUS "pushpred Python module: built for ${Python3_EXECUTABLE} (Python ${Python3_VERSION}, "
               "pybind11 ${pybind11_VERSION}); pytest tests: ${PUSHPRED_PYTEST_FOUND}")
set(PUSHPRED_PYTHON_ENABLED ON)
