# Code in lib/ that only the tests and benchmarks use (TOOLINC_TEST_ONLY_SOURCES: the ONNX writer that
# makes test networks), kept out of the installed library, plus the library and the command-line glue the tests drive.
add_library(toolinc_test_support STATIC ${TOOLINC_TEST_ONLY_SOURCES})
target_compile_options(toolinc_test_support PRIVATE -Wall -Wextra)
target_link_libraries(toolinc_test_support PUBLIC toolinc toolinc_app PRIVATE spdlog::spdlog)
