# The Python module's dependencies (Debian: python3-dev, python3-numpy, pybind11-dev; the tests:
# python3-pytest). Debian's interpreter is the one whose packages tools/debian-packages.txt
# installs: a python3 found first on PATH (pyenv's, a venv's) may lack numpy, so /usr/bin/python3
# is preferred unless Python3_EXECUTABLE is given. Sets CREX_WITH_PYTHON and CREX_PYTHON_EXECUTABLE.
set(CREX_WITH_PYTHON OFF)
if(NOT Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  set(Python3_EXECUTABLE /usr/bin/python3)
endif()
find_package(Python3 COMPONENTS Interpreter Development.Module NumPy QUIET)
if(Python3_FOUND)
  find_package(pybind11 CONFIG QUIET)
endif()
if(Python3_FOUND AND Python3_NumPy_FOUND AND pybind11_FOUND)
  set(CREX_WITH_PYTHON ON)
  set(CREX_PYTHON_EXECUTABLE "${Python3_EXECUTABLE}")
  # Where `cmake --install` puts the package: where Debian's python3 looks under the prefix.
  set(CREX_PYTHON_INSTALL_DIR "lib/python${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}/dist-packages" CACHE STRING
      "Where the crex Python package is installed, relative to the prefix")
  message(STATUS "crex: the Python module for ${Python3_EXECUTABLE} (${Python3_VERSION}), pybind11 ${pybind11_VERSION}")
else()
  message(STATUS "crex: no Python module (needs python3-dev, python3-numpy and pybind11-dev)")
endif()
