// Running the batch workflows (scripts/pipeline.mk, scripts/Snakefile) from tests, and reading the
// summary.csv both write.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "support/paths.hpp"
#include "support/run_tool.hpp"
#include "toolinc/io/json_file.hpp"

namespace toolinc::testing {

// Runs a shell command, its output to `log`; returns the exit status.
inline int shell(const std::string& command, const std::filesystem::path& log) {
  const int status = std::system((command + " >" + log.string() + " 2>&1 </dev/null").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// One CSV line's cells (RFC 4180 quoting: a cell with a comma or a quote is quoted, its quotes doubled).
inline std::vector<std::string> csv_cells(const std::string& line) {
  std::vector<std::string> out(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"')
      out.back() += line[++i];
    else if (c == '"')
      quoted = !quoted;
    else if (c == ',' && !quoted)
      out.emplace_back();
    else
      out.back() += c;
  }
  return out;
}

// summary.csv as rows keyed by session, each a map from column to cell; `header` gets the columns.
inline std::map<std::string, std::map<std::string, std::string>> read_summary(const std::filesystem::path& path,
                                                                              std::vector<std::string>* header) {
  std::istringstream csv(slurp(path));
  std::string line;
  std::map<std::string, std::map<std::string, std::string>> rows;
  if (!std::getline(csv, line)) return rows;
  *header = csv_cells(line);
  while (std::getline(csv, line)) {
    const auto cells = csv_cells(line);
    std::map<std::string, std::string> row;
    for (std::size_t i = 0; i < cells.size() && i < header->size(); ++i) row[(*header)[i]] = cells[i];
    if (cells.size() != header->size()) row["_error"] = "cells: " + std::to_string(cells.size());
    rows[row["session"]] = row;
  }
  return rows;
}

// simulate-session's session, with ideal stereo (fast, and every step succeeds on it).
inline int simulate_session(const std::filesystem::path& folder, const std::string& family, int seed) {
  return run_tool("simulate-session",
                  "-q --stereo ideal --family " + family + " --seed " + std::to_string(seed) + " -o " + folder.string())
      .exit_code;
}

using SummaryRow = std::map<std::string, std::string>;

// A done session's row agrees with its outputs in `folder` (OUT/NAME), which are all there.
inline void expect_done(const SummaryRow& row, const std::filesystem::path& folder) {
  SCOPED_TRACE(folder.string());
  EXPECT_EQ(row.count("_error"), 0u) << row.at("_error");
  EXPECT_EQ(row.at("status"), "done");
  EXPECT_EQ(row.at("failure"), "");
  for (const char* file : {"views/view_000.ply", "model.ply", "frame.json", "model.png", "sheet.png", "report.html"})
    EXPECT_TRUE(std::filesystem::exists(folder / file)) << file;
  const Json merge = read_json((folder / "merge_report.json").string());
  int accepted = 0;
  for (const auto& v : merge["views"]) accepted += v["accepted"].get<bool>();
  EXPECT_EQ(number(row.at("views")), static_cast<double>(merge["views"].size()));
  EXPECT_EQ(number(row.at("views_accepted")), accepted);
  const Json tip = read_json((folder / "tooltip.json").string());
  const char* axes[] = {"tooltip_x", "tooltip_y", "tooltip_z"};
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(number(row.at(axes[a])), tip["position"][a].get<double>(), 1e-6);
}

// A failed session's row: no figures, the failed step and its error (which starts with `failure`).
inline void expect_failed(const SummaryRow& row, const std::string& failure) {
  SCOPED_TRACE(row.at("session"));
  EXPECT_EQ(row.count("_error"), 0u) << row.at("_error");
  EXPECT_EQ(row.at("status"), "failed");
  EXPECT_EQ(row.at("failure").rfind(failure, 0), 0u) << row.at("failure");
  for (const char* column : {"views", "views_accepted", "tooltip_x", "tooltip_error_mm"})
    EXPECT_EQ(row.at(column), "") << column;
}

}  // namespace toolinc::testing
