// Feature vectors as text, in the layout of the iCub recognition modules' databases
// (original-method.md sect. 10), so existing robot databases can be reused without images:
// DIR/<label>/<n>.txt, one vector per line, whitespace-separated numbers.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

namespace toolinc {

struct LabelledFeatures {
  std::vector<std::string> labels;  // one per row
  std::vector<Eigen::VectorXd> rows;
};

// Every line a vector (blank lines skipped). Throws InputError(path, ...) naming the line when a value is
// not a finite number or the rows differ in length, and when there is no row at all.
std::vector<Eigen::VectorXd> read_feature_rows(const std::string& path);
// Atomically; values in their shortest round-trip form.
void write_feature_rows(const std::string& path, const std::vector<Eigen::VectorXd>& rows);

// Labels in name order, each label's files in the order of their number n. Throws InputError(dir, ...)
// when the folder holds no labelled vectors or vectors of different lengths.
LabelledFeatures read_feature_db(const std::string& dir);
// DIR/<label>/0.txt per label, creating the folders; the labels must be usable as folder names.
void write_feature_db(const std::string& dir, const LabelledFeatures& features);

}  // namespace toolinc
