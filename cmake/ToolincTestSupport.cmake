# What the tests and benchmarks share (tests/support/: running the executables, writing inputs, synthetic
# cases, the ONNX writer that makes test networks), plus the library and the command-line glue they drive.
file(GLOB TOOLINC_TEST_SUPPORT_SOURCES CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/tests/support/*.cpp)
# This build's folders in one generated file (support/paths.hpp says why).
configure_file(${PROJECT_SOURCE_DIR}/tests/support/test_paths.cpp.in ${PROJECT_BINARY_DIR}/tests/test_paths.cpp @ONLY)
add_library(toolinc_test_support STATIC ${TOOLINC_TEST_SUPPORT_SOURCES} ${PROJECT_BINARY_DIR}/tests/test_paths.cpp)
# The internals' headers under lib/ too: their unit tests include them.
target_include_directories(toolinc_test_support PUBLIC ${PROJECT_SOURCE_DIR}/tests ${PROJECT_SOURCE_DIR}/lib)
target_compile_options(toolinc_test_support PRIVATE -Wall -Wextra)
target_link_libraries(toolinc_test_support PUBLIC toolinc toolinc_app PRIVATE spdlog::spdlog)
