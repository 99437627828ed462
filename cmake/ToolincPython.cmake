# The `toolinc` Python module (python/), built when pybind11 is found (TOOLINC_BUILD_PYTHON=AUTO) and
# installed beside the library, in TOOLINC_PYTHON_INSTALL_DIR under the prefix.
set(TOOLINC_BUILD_PYTHON AUTO CACHE STRING "Build the Python module: AUTO (when pybind11 is found), ON or OFF")
set_property(CACHE TOOLINC_BUILD_PYTHON PROPERTY STRINGS AUTO ON OFF)
set(TOOLINC_PYTHON_INSTALL_DIR ${CMAKE_INSTALL_LIBDIR}/python3/dist-packages CACHE STRING
    "Where the Python module is installed, relative to the prefix")
set(TOOLINC_PYTHON FALSE)
if(NOT TOOLINC_BUILD_PYTHON STREQUAL "OFF")
  if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    # The system interpreter, whose numpy and pytest Debian provides (not a user's pyenv shim first on PATH).
    set(Python3_EXECUTABLE /usr/bin/python3)
  endif()
  set(PYBIND11_FINDPYTHON ON)
  if(TOOLINC_BUILD_PYTHON STREQUAL "ON")
    find_package(Python3 REQUIRED COMPONENTS Interpreter Development.Module)
    find_package(pybind11 CONFIG REQUIRED)
  else()
    find_package(Python3 QUIET COMPONENTS Interpreter Development.Module)
    if(Python3_FOUND)
      find_package(pybind11 CONFIG QUIET)
    endif()
  endif()
  if(pybind11_FOUND)
    set(TOOLINC_PYTHON TRUE)
  endif()
endif()
message(STATUS "toolinc: Python module ${TOOLINC_PYTHON} (TOOLINC_BUILD_PYTHON=${TOOLINC_BUILD_PYTHON})")

if(TOOLINC_PYTHON)
  # No link-time optimisation (pybind11's default): the module is one file over static libraries built
  # without it, so LTO had nothing to inline across and cost a serial 7-partition link.
  set(CMAKE_INTERPROCEDURAL_OPTIMIZATION OFF)
  pybind11_add_module(toolinc_python MODULE ${PROJECT_SOURCE_DIR}/python/toolinc_module.cpp)
  set_target_properties(toolinc_python PROPERTIES OUTPUT_NAME toolinc
                                                  LIBRARY_OUTPUT_DIRECTORY ${PROJECT_BINARY_DIR}/python)
  target_compile_definitions(toolinc_python PRIVATE TOOLINC_VERSION="${PROJECT_VERSION}")
  target_link_libraries(toolinc_python PRIVATE toolinc_app)
  install(TARGETS toolinc_python LIBRARY DESTINATION ${TOOLINC_PYTHON_INSTALL_DIR})
endif()
