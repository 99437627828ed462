# Tests of toolinc as a package: the install and the examples against it (tests/package), the result
# files against docs/schemas and the Python module (tests/python, pytest).
find_program(TOOLINC_TEST_PYTHON NAMES python3 HINTS /usr/bin NO_DEFAULT_PATH)
find_program(TOOLINC_TEST_PYTHON NAMES python3)
if(Python3_EXECUTABLE)
  set(TOOLINC_TEST_PYTHON ${Python3_EXECUTABLE})
endif()

add_test(NAME package_install_and_examples
         COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${PROJECT_SOURCE_DIR} -DBUILD_DIR=${PROJECT_BINARY_DIR}
                 -DWORK_DIR=${PROJECT_BINARY_DIR}/package-test -DINTERPRETER=${TOOLINC_TEST_PYTHON}
                 -DPYTHON=${TOOLINC_PYTHON} -P ${PROJECT_SOURCE_DIR}/tests/package/check_package.cmake)
set_tests_properties(package_install_and_examples PROPERTIES TIMEOUT 900 RUN_SERIAL TRUE LABELS integration)

set(python_test_env TOOLINC_BIN_DIR=${PROJECT_BINARY_DIR}/bin TOOLINC_SOURCE_DIR=${PROJECT_SOURCE_DIR}
                    PYTHONPATH=${PROJECT_BINARY_DIR}/python PYTHONDONTWRITEBYTECODE=1)
add_test(NAME python_schemas
         COMMAND ${TOOLINC_TEST_PYTHON} -m pytest -q -p no:cacheprovider ${PROJECT_SOURCE_DIR}/tests/python/test_schemas.py)
set_tests_properties(python_schemas PROPERTIES ENVIRONMENT "${python_test_env}" TIMEOUT 600 LABELS unit)
if(TOOLINC_PYTHON)
  add_test(NAME python_module
           COMMAND ${TOOLINC_TEST_PYTHON} -m pytest -q -p no:cacheprovider ${PROJECT_SOURCE_DIR}/tests/python/test_module.py)
  set_tests_properties(python_module PROPERTIES ENVIRONMENT "${python_test_env}" TIMEOUT 600 LABELS unit)
endif()
