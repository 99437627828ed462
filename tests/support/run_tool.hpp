// Running the project's executables from tests: exit code and what they printed.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/paths.hpp"

namespace toolinc::testing {

struct ToolRun {
  int exit_code;
  std::string out, err;
};

inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  return buffer.str();
}

// Runs bin/<tool> with the given (already shell-quoted) arguments.
inline ToolRun run_tool(const std::string& tool, const std::string& args) {
  static int counter = 0;
  const auto dir = std::filesystem::temp_directory_path() / ("toolinc-run-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto out = dir / ("out" + std::to_string(counter)), err = dir / ("err" + std::to_string(counter++));
  const std::string command = std::string(toolinc::testing::kBinDir) + "/" + tool + " " + args + " >" + out.string() +
                              " 2>" + err.string() + " </dev/null";
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(out), slurp(err)};
}

// A fresh empty folder for one test.
inline std::filesystem::path scratch_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("toolinc-test-" + std::to_string(::getpid())) / name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// The error lines of what a run printed on stderr.
inline std::vector<std::string> error_lines(const std::string& err) {
  std::istringstream lines(err);
  std::vector<std::string> errors;
  for (std::string line; std::getline(lines, line);)
    if (line.find(": error: ") != std::string::npos) errors.push_back(line);
  return errors;
}

// A failed run as users must see it: exactly one error line on stderr, naming `word`, and neither the
// output nor a temporary file left in `dir`.
inline void expect_failure_left_nothing(const ToolRun& run, const std::string& word,
                                        const std::filesystem::path& output, const std::filesystem::path& dir) {
  const auto errors = error_lines(run.err);
  ASSERT_EQ(errors.size(), 1u) << run.err;
  EXPECT_NE(errors[0].find(word), std::string::npos) << errors[0];
  EXPECT_FALSE(std::filesystem::exists(output)) << output;
  for (const auto& entry : std::filesystem::directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << "temporary file left: " << entry.path();
}

// Runs `tool args -o output`, which must exit with `code` and fail as above.
inline void expect_clean_failure(const std::string& tool, const std::string& args, const std::filesystem::path& output,
                                 int code, const std::string& word) {
  const auto run = run_tool(tool, args + " -o " + output.string());
  SCOPED_TRACE(tool + " " + args + "\n" + run.err);
  EXPECT_EQ(run.exit_code, code);
  expect_failure_left_nothing(run, word, output, output.parent_path());
}

// A table cell that must be a number and nothing else.
inline double number(const std::string& cell) {
  std::size_t used = 0;
  const double value = std::stod(cell, &used);
  EXPECT_EQ(used, cell.size()) << cell;
  return value;
}

}  // namespace toolinc::testing
