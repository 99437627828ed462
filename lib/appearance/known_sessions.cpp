#include "toolinc/appearance/known_sessions.hpp"

#include <spdlog/fmt/fmt.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>

#include "toolinc/core/error.hpp"

namespace toolinc {

KnownSessions known_sessions(const Eigen::MatrixXd& x, const std::vector<std::size_t>& targets,
                             const std::vector<std::size_t>& groups, Eigen::Index start, Eigen::Index size) {
  std::map<std::size_t, std::vector<Eigen::Index>> rows;  // per session, in the order of their ids
  for (std::size_t i = 0; i < groups.size(); ++i) rows[groups[i]].push_back(static_cast<Eigen::Index>(i));
  KnownSessions known;
  known.start = start, known.size = size;
  known.means.resize(static_cast<Eigen::Index>(rows.size()), size);
  for (const auto& [group, members] : rows) {
    known.means.row(static_cast<Eigen::Index>(known.labels.size())) = x(members, Eigen::seqN(start, size)).colwise().mean();
    known.labels.push_back(targets[static_cast<std::size_t>(members.front())]);
  }
  return known;
}

double sibling_radius(const KnownSessions& known) {
  double radius = -std::numeric_limits<double>::infinity();
  for (Eigen::Index s = 0; s < known.means.rows(); ++s) {
    double nearest = std::numeric_limits<double>::infinity();
    for (Eigen::Index o = 0; o < known.means.rows(); ++o)
      if (o != s && known.labels[static_cast<std::size_t>(o)] == known.labels[static_cast<std::size_t>(s)])
        nearest = std::min(nearest, (known.means.row(o) - known.means.row(s)).norm());
    if (std::isfinite(nearest)) radius = std::max(radius, nearest);
  }
  return std::isfinite(radius) ? radius : std::numeric_limits<double>::infinity();
}

double distance_to_label(const KnownSessions& known, const Eigen::MatrixXd& rows, std::size_t label) {
  const Eigen::RowVectorXd mean = rows.middleCols(known.start, known.size).colwise().mean();
  double nearest = std::numeric_limits<double>::infinity();
  for (Eigen::Index s = 0; s < known.means.rows(); ++s)
    if (known.labels[static_cast<std::size_t>(s)] == label) nearest = std::min(nearest, (known.means.row(s) - mean).norm());
  return nearest;
}

Json to_json(const KnownSessions& known) {
  Json sessions = Json::array();
  for (Eigen::Index s = 0; s < known.means.rows(); ++s) {
    const Eigen::RowVectorXd mean = known.means.row(s);  // a row of a column-major matrix is strided
    sessions.push_back({{"label", known.labels[static_cast<std::size_t>(s)]},
                        {"mean", std::vector<double>(mean.data(), mean.data() + mean.size())}});
  }
  return {{"start", known.start}, {"size", known.size}, {"sessions", sessions}};
}

KnownSessions known_sessions_from_json(const Json& json, std::size_t labels, Eigen::Index dimension,
                                       const std::string& file) {
  const auto fail = [&](const std::string& what) { return InputError(file, "known_sessions: " + what); };
  if (!json.is_object() || !json.value("start", Json()).is_number_unsigned() ||
      !json.value("size", Json()).is_number_unsigned() || !json.value("sessions", Json()).is_array())
    throw fail("expected \"start\", \"size\" and \"sessions\"");
  const auto start = json["start"].get<std::uint64_t>(), size = json["size"].get<std::uint64_t>();
  if (size == 0 || start > static_cast<std::uint64_t>(dimension) || size > static_cast<std::uint64_t>(dimension) - start)
    throw fail("the columns are not inside the features");
  KnownSessions known;
  known.start = static_cast<Eigen::Index>(start), known.size = static_cast<Eigen::Index>(size);
  known.means.resize(static_cast<Eigen::Index>(json["sessions"].size()), known.size);
  for (const auto& session : json["sessions"]) {
    if (!session.is_object()) throw fail("a session must be {\"label\", \"mean\"}");
    const Json& label = session.value("label", Json());
    const Json& mean = session.value("mean", Json());
    if (!label.is_number_unsigned() || label.get<std::size_t>() >= labels)
      throw fail("a session's \"label\" is not a label index");
    if (!mean.is_array() || static_cast<Eigen::Index>(mean.size()) != known.size)
      throw fail(fmt::format("a session's \"mean\" must hold {} numbers", known.size));
    const auto row = static_cast<Eigen::Index>(known.labels.size());
    for (Eigen::Index i = 0; i < known.size; ++i) {
      const Json& value = mean[static_cast<std::size_t>(i)];
      if (!value.is_number() || !std::isfinite(value.get<double>())) throw fail("a session's \"mean\" must be finite numbers");
      known.means(row, i) = value.get<double>();
    }
    known.labels.push_back(label.get<std::size_t>());
  }
  return known;
}

}  // namespace toolinc
