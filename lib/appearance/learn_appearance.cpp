#include "toolinc/appearance/learn_appearance.hpp"

#include <spdlog/fmt/fmt.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "toolinc/appearance/crops.hpp"
#include "toolinc/appearance/unknown_floor.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/read_file.hpp"
#include "toolinc/session/session.hpp"

namespace toolinc {
namespace {
namespace fs = std::filesystem;

void check_label(const std::string& label, const std::string& file) {
  if (label.empty() || label == kUnknownLabel || label.find_first_of(" \t\n/") != std::string::npos)
    throw InputError(
        file, fmt::format("label \"{}\" is not usable (empty, \"{}\", or with spaces or /)", label, kUnknownLabel));
}

void add_session(const std::string& dir, const std::string& label_override, const FeatureExtractor& extractor,
                 LabelledFeatures& out) {
  const SessionInfo session = read_session(dir);
  const std::string session_file = (fs::path(dir) / "session.json").string();
  const std::string label = label_override.empty() ? session.tool_label.value_or("") : label_override;
  if (label.empty()) throw InputError(session_file, "no tool_label: give --label");
  check_label(label, session_file);
  for (const auto& crop : session_crops(dir, session)) {
    out.labels.push_back(label);
    out.rows.push_back(extractor.extract(crop.image, crop.mask, crop.points));
  }
}

void add_image_list(const std::string& list, const FeatureExtractor& extractor, LabelledFeatures& out) {
  std::istringstream text(read_file(list));
  std::size_t line_number = 0;
  for (std::string line; std::getline(text, line);) {
    ++line_number;
    std::istringstream fields(line);
    std::string path, label;
    cv::Rect box;
    if (!(fields >> path) || path[0] == '#') continue;
    if (!(fields >> label >> box.x >> box.y >> box.width >> box.height) || !(fields >> std::ws).eof())
      throw InputError(list, fmt::format("line {}: expected \"path label x y w h\"", line_number));
    check_label(label, fmt::format("{}: line {}", list, line_number));
    if (fs::path(path).is_relative()) path = (fs::path(list).parent_path() / path).string();
    const cv::Mat image = read_image(path);
    check_box_inside(box, image.size(), path);
    if (box.area() == 0) throw InputError(path, fmt::format("empty box (line {} of {})", line_number, list));
    out.labels.push_back(label);
    out.rows.push_back(extractor.extract(image(crop_around(box, image.size()))));
  }
}

FeatureExtractor choose_extractor(const TrainingSources& sources, const std::optional<DnnFeatureConfig>& backbone,
                                  const std::optional<LabelledFeatures>& database) {
  if (backbone) return FeatureExtractor::dnn(*backbone);
  if (!sources.sessions.empty() || !sources.images.empty()) return FeatureExtractor::builtin();
  return FeatureExtractor::external(database->rows.front().size());
}

Eigen::MatrixXd stack(const std::vector<Eigen::VectorXd>& rows) {
  Eigen::MatrixXd matrix(static_cast<Eigen::Index>(rows.size()), rows.empty() ? 0 : rows.front().size());
  for (std::size_t i = 0; i < rows.size(); ++i) matrix.row(static_cast<Eigen::Index>(i)) = rows[i].transpose();
  return matrix;
}

Json box_json(const cv::Rect& box) { return Json::array({box.x, box.y, box.width, box.height}); }

}  // namespace

AppearanceClassifier train_appearance(const TrainingSources& sources, const std::optional<DnnFeatureConfig>& backbone,
                                      const RlsConfig& rls, Json& training_summary) {
  if (sources.sessions.empty() && sources.images.empty() && sources.features_db.empty())
    throw std::invalid_argument("no training data: give --session, --images or --features-db");
  if (!sources.label.empty()) check_label(sources.label, "--label");
  std::optional<LabelledFeatures> database;
  if (!sources.features_db.empty()) database = read_feature_db(sources.features_db);
  const FeatureExtractor extractor = choose_extractor(sources, backbone, database);
  if (database) {
    if (database->rows.front().size() != extractor.dimension())
      throw InputError(sources.features_db,
                       fmt::format("vectors of {} values, but the {} extractor gives {}", database->rows.front().size(),
                                   extractor.name(), extractor.dimension()));
    for (const auto& label : database->labels) check_label(label, sources.features_db);
  }

  LabelledFeatures data;
  std::vector<std::size_t> groups;  // a session's views form one group, any other sample its own
  std::size_t next_group = 0;
  for (const auto& session : sources.sessions) {
    add_session(session, sources.label, extractor, data);
    groups.resize(data.rows.size(), next_group++);
  }
  if (!sources.images.empty()) add_image_list(sources.images, extractor, data);
  if (database) {
    data.labels.insert(data.labels.end(), database->labels.begin(), database->labels.end());
    data.rows.insert(data.rows.end(), database->rows.begin(), database->rows.end());
  }

  std::map<std::string, std::size_t> counts;
  for (const auto& label : data.labels) ++counts[label];
  std::vector<std::string> labels;
  for (const auto& [label, count] : counts) labels.push_back(label);
  std::vector<std::size_t> targets;
  for (const auto& label : data.labels)
    targets.push_back(static_cast<std::size_t>(std::lower_bound(labels.begin(), labels.end(), label) - labels.begin()));
  spdlog::info("training on {} samples of {} label(s), {} {} features each", data.rows.size(), labels.size(),
               extractor.dimension(), extractor.name());
  Eigen::MatrixXd x = stack(data.rows);
  while (groups.size() < data.rows.size()) groups.push_back(next_group++);
  RlsModel model;
  Json block_weights = Json::object();
  if (extractor.name() == "builtin") {
    // First how much the image's shape blocks count beside the depth block (a turn about the handle
    // changes the first, not the second), then colour, each by leave-one-session-out.
    const auto blocks = builtin_blocks(extractor.builtin_config());
    const FeatureBlock& colour = blocks.back();
    const FeatureBlock& depth = blocks[blocks.size() - 2];
    const double image_weight = weigh_block(x, targets, labels, groups, 0, depth.start, rls, model);
    const double colour_weight = weigh_block(x, targets, labels, groups, colour.start, colour.size, rls, model);
    block_weights = {{"image_shape", image_weight},
                     {"colour", colour_weight},
                     {"from", "leave-one-session-out error among 1, 1/2, 1/4, 1/8 and 0, image shape blocks first"}};
    spdlog::info("image shape blocks weight {}, colour block weight {} (leave-one-session-out)", image_weight,
                 colour_weight);
  } else {
    model = train_rls(x, targets, labels, rls);
  }
  spdlog::info("lambda {:.3g} by leave-one-out: error {:.4f}, accuracy {:.1f}%", model.lambda, model.loo_error,
               100.0 * model.loo_accuracy);
  Json calibration;
  const bool sessions_only = sources.images.empty() && !database;
  DecisionConfig decision = calibrate_decision(x, targets, labels, groups, sessions_only, model, rls, {}, calibration);
  std::optional<KnownSessions> known;
  if (extractor.name() == "builtin") {  // the weights move into the model's rows: the extractor stays as it is
    const auto blocks = builtin_blocks(extractor.builtin_config());
    if (sessions_only && !sources.sessions.empty()) {
      const FeatureBlock& depth = blocks[blocks.size() - 2];
      known = known_sessions(x, targets, groups, depth.start, depth.size);
      decision.max_distance = sibling_radius(*known);
      calibration["max_distance_from"] =
          "the largest distance from a training session's mean depth block to the nearest other session of its label";
      spdlog::info("unknown beyond {:.3f} from every training session of the answer (depth block)",
                   decision.max_distance);
    }
    model.weights.topRows(blocks[blocks.size() - 2].start) *= block_weights["image_shape"].get<double>();
    model.weights.middleRows(blocks.back().start, blocks.back().size) *= block_weights["colour"].get<double>();
  }

  training_summary = {{"samples", data.rows.size()}, {"per_label", counts},      {"sessions", sources.sessions},
                      {"label", sources.label},      {"images", sources.images}, {"features_db", sources.features_db}};
  if (!block_weights.empty()) training_summary["block_weights"] = block_weights;
  return {extractor, std::move(model), decision, calibration, std::move(known)};
}

Json classify_appearance(const AppearanceClassifier& classifier, const std::string& classifier_path,
                         const ClassifyInput& input, const DecisionConfig& decision) {
  const int given = !input.session.empty() + !input.image.empty() + !input.features.empty();
  if (given != 1) throw std::invalid_argument("give exactly one of --session, --image (with --bbox) or --features");
  if (input.image.empty() == input.bbox.has_value()) throw std::invalid_argument("--image and --bbox go together");
  if (input.view && input.session.empty()) throw std::invalid_argument("--view needs --session");
  const FeatureExtractor& extractor = classifier.extractor;
  const std::vector<std::string>& labels = classifier.model.labels;
  if (input.features.empty() && !extractor.extracts_from_images())
    throw InputError(classifier_path, "trained on external features: only --features can be classified");

  std::vector<Eigen::VectorXd> rows;
  std::vector<Json> samples;
  Json source;
  if (!input.session.empty()) {
    for (const auto& crop : session_crops(input.session, read_session(input.session), input.view)) {
      rows.push_back(extractor.extract(crop.image, crop.mask, crop.points));
      samples.push_back({{"view", crop.view}, {"box", box_json(crop.box)}});
    }
    source = {{"session", input.session}};
  } else if (!input.image.empty()) {
    const cv::Mat image = read_image(input.image);
    check_box_inside(*input.bbox, image.size(), input.image);
    const cv::Rect crop = crop_around(*input.bbox, image.size());
    rows.push_back(extractor.extract(image(crop)));
    samples.push_back({{"image", input.image}, {"box", box_json(crop)}});
    source = {{"image", input.image}, {"bbox", box_json(*input.bbox)}};
  } else {
    rows = read_feature_rows(input.features);
    if (rows.front().size() != extractor.dimension())
      throw InputError(input.features,
                       fmt::format("rows of {} values, but {} expects {} ({} features)", rows.front().size(),
                                   classifier_path, extractor.dimension(), extractor.name()));
    for (std::size_t i = 0; i < rows.size(); ++i) samples.push_back({{"row", i}});
    source = {{"features", input.features}};
  }
  const Json context = {{"classifier", classifier_path}, {"extractor", extractor.name()}, {"input", source}};
  const Eigen::MatrixXd features = stack(rows);
  Json result =
      classification_json(labels, rls_scores(classifier.model, features), std::move(samples), decision, context);
  // A whole session whose head lies farther from every training session of its answer than any training
  // session lies from its nearest sibling is a tool never seen (known_sessions.hpp), unless it scores
  // higher than any tool never seen did in training.
  const auto answer = std::find(labels.begin(), labels.end(), result["label"].get<std::string>());
  if (classifier.known && !input.session.empty() && !input.view && std::isfinite(decision.max_distance) &&
      answer != labels.end()) {
    const auto label = static_cast<std::size_t>(answer - labels.begin());
    const double distance = distance_to_label(*classifier.known, features, label);
    result["distance"] = distance;
    result["max_distance"] = decision.max_distance;
    if (std::isfinite(decision.sure_score)) result["sure_score"] = decision.sure_score;
    if (distance > decision.max_distance && !(result["best_score"].get<double>() > decision.sure_score))
      result["label"] = kUnknownLabel;
  }
  return result;
}

}  // namespace toolinc
