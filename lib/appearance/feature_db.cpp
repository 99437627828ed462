#include "toolinc/appearance/feature_db.hpp"

#include <spdlog/fmt/fmt.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include "toolinc/core/error.hpp"
#include "toolinc/io/atomic_file.hpp"
#include "toolinc/io/read_file.hpp"

namespace toolinc {
namespace fs = std::filesystem;

std::vector<Eigen::VectorXd> read_feature_rows(const std::string& path) {
  std::istringstream text(read_file(path));
  std::vector<Eigen::VectorXd> rows;
  std::size_t line_number = 0;
  for (std::string line; std::getline(text, line);) {
    ++line_number;
    std::vector<double> values;
    std::istringstream fields(line);
    for (std::string field; fields >> field;) {
      errno = 0;
      char* end = nullptr;
      const double value = std::strtod(field.c_str(), &end);
      if (*end != '\0' || errno == ERANGE || !std::isfinite(value))
        throw InputError(path, fmt::format("line {}: \"{}\" is not a finite number", line_number, field));
      values.push_back(value);
    }
    if (values.empty()) continue;
    if (!rows.empty() && static_cast<Eigen::Index>(values.size()) != rows.front().size())
      throw InputError(path, fmt::format("line {}: {} values, but the first row has {}", line_number, values.size(),
                                         rows.front().size()));
    rows.push_back(Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size())));
  }
  if (rows.empty()) throw InputError(path, "no feature vectors");
  return rows;
}

void write_feature_rows(const std::string& path, const std::vector<Eigen::VectorXd>& rows) {
  write_file_atomic(path, [&](std::ostream& out) {
    for (const auto& row : rows) {
      for (Eigen::Index i = 0; i < row.size(); ++i) out << (i ? " " : "") << fmt::format("{}", row[i]);
      out << '\n';
    }
  });
}

namespace {

// The files of one label folder in the order of their number (then name, for names that are not numbers).
std::vector<fs::path> numbered_files(const fs::path& folder) {
  std::vector<std::pair<long, fs::path>> files;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file() || entry.path().extension() != ".txt") continue;
    char* end = nullptr;
    const std::string stem = entry.path().stem().string();
    const long n = std::strtol(stem.c_str(), &end, 10);
    files.emplace_back(*end == '\0' && !stem.empty() ? n : -1, entry.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<fs::path> paths;
  for (auto& file : files) paths.push_back(std::move(file.second));
  return paths;
}

}  // namespace

LabelledFeatures read_feature_db(const std::string& dir) {
  if (!fs::is_directory(dir)) throw InputError(dir, "not a folder");
  std::map<std::string, fs::path> labels;  // sorted by name
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_directory()) labels.emplace(entry.path().filename().string(), entry.path());
  LabelledFeatures db;
  std::string first_file;
  for (const auto& [label, folder] : labels)
    for (const auto& file : numbered_files(folder))
      for (auto& row : read_feature_rows(file.string())) {
        if (!db.rows.empty() && row.size() != db.rows.front().size())
          throw InputError(file.string(), fmt::format("vectors of {} values, but {} has {}", row.size(), first_file,
                                                      db.rows.front().size()));
        if (db.rows.empty()) first_file = file.string();
        db.labels.push_back(label);
        db.rows.push_back(std::move(row));
      }
  if (db.rows.empty()) throw InputError(dir, "no feature vectors in DIR/<label>/<n>.txt files");
  return db;
}

void write_feature_db(const std::string& dir, const LabelledFeatures& features) {
  std::map<std::string, std::vector<Eigen::VectorXd>> by_label;
  for (std::size_t i = 0; i < features.rows.size(); ++i) by_label[features.labels[i]].push_back(features.rows[i]);
  for (const auto& [label, rows] : by_label) {
    const fs::path folder = fs::path(dir) / label;
    std::error_code error;
    fs::create_directories(folder, error);
    if (error) throw InputError(folder.string(), "cannot create: " + error.message());
    write_feature_rows((folder / "0.txt").string(), rows);
  }
}

}  // namespace toolinc
