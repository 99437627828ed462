#include "toolinc/appearance/known_sessions.hpp"

#include <spdlog/fmt/fmt.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>

#include "toolinc/core/error.hpp"

namespace toolinc {

namespace {

// Per column the spread between sessions of one label (pooled over labels), plus the mean spread of all
// columns: what a column's distance is divided by, so that a column that changes from grasp to grasp
// weighs little and a steady one much, but no column weighs without bound. Ones when no label has two
// sessions.
Eigen::RowVectorXd spread_scale(const KnownSessions& known) {
  std::map<std::size_t, std::vector<Eigen::Index>> per_label;
  for (Eigen::Index s = 0; s < known.means.rows(); ++s)
    per_label[known.labels[static_cast<std::size_t>(s)]].push_back(s);
  Eigen::RowVectorXd squares = Eigen::RowVectorXd::Zero(known.size);
  Eigen::Index dof = 0;
  for (const auto& [label, sessions] : per_label) {
    const Eigen::MatrixXd means = known.means(sessions, Eigen::all);
    squares += (means.rowwise() - means.colwise().mean()).array().square().colwise().sum().matrix();
    dof += static_cast<Eigen::Index>(sessions.size()) - 1;
  }
  if (dof == 0 || squares.sum() == 0) return Eigen::RowVectorXd::Ones(known.size);
  const Eigen::RowVectorXd variance = squares / static_cast<double>(dof);
  return (variance.array() + variance.mean()).rsqrt().matrix();
}

// Distance between two rows of the compared columns, each column in its own unit (scale).
double scaled_distance(const KnownSessions& known, const Eigen::RowVectorXd& a, const Eigen::RowVectorXd& b) {
  return (a - b).cwiseProduct(known.scale).norm();
}

}  // namespace

KnownSessions known_sessions(const Eigen::MatrixXd& x, const std::vector<std::size_t>& targets,
                             const std::vector<std::size_t>& groups, Eigen::Index start, Eigen::Index size) {
  std::map<std::size_t, std::vector<Eigen::Index>> rows;  // per session, in the order of their ids
  for (std::size_t i = 0; i < groups.size(); ++i) rows[groups[i]].push_back(static_cast<Eigen::Index>(i));
  KnownSessions known;
  known.start = start, known.size = size;
  known.means.resize(static_cast<Eigen::Index>(rows.size()), size);
  for (const auto& [group, members] : rows) {
    known.means.row(static_cast<Eigen::Index>(known.labels.size())) =
        x(members, Eigen::seqN(start, size)).colwise().mean();
    known.labels.push_back(targets[static_cast<std::size_t>(members.front())]);
  }
  known.scale = spread_scale(known);
  return known;
}

double sibling_radius(const KnownSessions& known) {
  double radius = -std::numeric_limits<double>::infinity();
  for (Eigen::Index s = 0; s < known.means.rows(); ++s) {
    double nearest = std::numeric_limits<double>::infinity();
    for (Eigen::Index o = 0; o < known.means.rows(); ++o)
      if (o != s && known.labels[static_cast<std::size_t>(o)] == known.labels[static_cast<std::size_t>(s)])
        nearest = std::min(nearest, scaled_distance(known, known.means.row(o), known.means.row(s)));
    if (std::isfinite(nearest)) radius = std::max(radius, nearest);
  }
  return std::isfinite(radius) ? radius : std::numeric_limits<double>::infinity();
}

double distance_to_label(const KnownSessions& known, const Eigen::MatrixXd& rows, std::size_t label) {
  const Eigen::RowVectorXd mean = rows.middleCols(known.start, known.size).colwise().mean();
  double nearest = std::numeric_limits<double>::infinity();
  for (Eigen::Index s = 0; s < known.means.rows(); ++s)
    if (known.labels[static_cast<std::size_t>(s)] == label)
      nearest = std::min(nearest, scaled_distance(known, known.means.row(s), mean));
  return nearest;
}

Json to_json(const KnownSessions& known) {
  Json sessions = Json::array();
  for (Eigen::Index s = 0; s < known.means.rows(); ++s) {
    const Eigen::RowVectorXd mean = known.means.row(s);  // a row of a column-major matrix is strided
    sessions.push_back({{"label", known.labels[static_cast<std::size_t>(s)]},
                        {"mean", std::vector<double>(mean.data(), mean.data() + mean.size())}});
  }
  return {{"start", known.start},
          {"size", known.size},
          {"scale", std::vector<double>(known.scale.data(), known.scale.data() + known.scale.size())},
          {"sessions", sessions}};
}

KnownSessions known_sessions_from_json(const Json& json, std::size_t labels, Eigen::Index dimension,
                                       const std::string& file) {
  const auto fail = [&](const std::string& what) { return InputError(file, "known_sessions: " + what); };
  if (!json.is_object() || !json.value("start", Json()).is_number_unsigned() ||
      !json.value("size", Json()).is_number_unsigned() || !json.value("scale", Json()).is_array() ||
      !json.value("sessions", Json()).is_array())
    throw fail("expected \"start\", \"size\", \"scale\" and \"sessions\"");
  const auto start = json["start"].get<std::uint64_t>(), size = json["size"].get<std::uint64_t>();
  if (size == 0 || start > static_cast<std::uint64_t>(dimension) ||
      size > static_cast<std::uint64_t>(dimension) - start)
    throw fail("the columns are not inside the features");
  KnownSessions known;
  known.start = static_cast<Eigen::Index>(start), known.size = static_cast<Eigen::Index>(size);
  const auto finite_numbers = [&](const Json& array, const std::string& what) {
    if (!array.is_array() || static_cast<Eigen::Index>(array.size()) != known.size)
      throw fail(fmt::format("{} must hold {} numbers", what, known.size));
    Eigen::RowVectorXd values(known.size);
    for (Eigen::Index i = 0; i < known.size; ++i) {
      const Json& value = array[static_cast<std::size_t>(i)];
      if (!value.is_number() || !std::isfinite(value.get<double>())) throw fail(what + " must be finite numbers");
      values[i] = value.get<double>();
    }
    return values;
  };
  known.scale = finite_numbers(json["scale"], "\"scale\"");
  if ((known.scale.array() <= 0).any()) throw fail("\"scale\" must be positive");
  known.means.resize(static_cast<Eigen::Index>(json["sessions"].size()), known.size);
  for (const auto& session : json["sessions"]) {
    if (!session.is_object()) throw fail("a session must be {\"label\", \"mean\"}");
    const Json& label = session.value("label", Json());
    const Json& mean = session.value("mean", Json());
    if (!label.is_number_unsigned() || label.get<std::size_t>() >= labels)
      throw fail("a session's \"label\" is not a label index");
    known.means.row(static_cast<Eigen::Index>(known.labels.size())) = finite_numbers(mean, "a session's \"mean\"");
    known.labels.push_back(label.get<std::size_t>());
  }
  return known;
}

}  // namespace toolinc
