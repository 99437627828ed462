// learn-appearance train|classify: learn tools' appearance from the crops of their exploration views and
// recognise them later (paper sect. 2; original-method.md sect. 10).
#include "toolinc/appearance/learn_appearance.hpp"

#include <spdlog/spdlog.h>

#include "toolinc/app/command.hpp"
#include "toolinc/appearance/crops.hpp"

namespace {

// An option given on the command line to the action it does not belong to is a usage error, not silently
// ignored. A config file's values are not: one file (configs/icub.json) holds the options of both actions.
// (CLI11 counts config values as given, so the command line itself is searched.)
std::vector<std::string> g_args;
void reject_options(const std::vector<CLI::Option*>& options, const std::string& action) {
  for (const auto* option : options) {
    const std::string name = option->get_name();
    for (const auto& arg : g_args)
      if (arg == name || arg.rfind(name + "=", 0) == 0)
        throw std::invalid_argument(name + " does not apply to " + action);
  }
}

}  // namespace

int main(int argc, char** argv) {
  toolinc::Command command("learn-appearance",
                           "Learn tools' appearance from exploration crops (train) and recognise them (classify)");
  auto& cli = command.cli();
  std::string action;
  cli.add_option("action", action, "train or classify")->required()->check(CLI::IsMember({"train", "classify"}));
  command.add_output("train: the classifier JSON; classify: the classification JSON (- for stdout)");

  toolinc::TrainingSources sources;
  std::string backbone;
  cli.add_option("--session", sources.sessions,
                 "Session folder(s): train on every view's crop; classify one session's views")
      ->expected(1, -1);
  cli.add_option("--backbone", backbone,
                 "ONNX network for dnn features (train); classify: the model file if not where the classifier says");

  std::vector<CLI::Option*> train_only = {
      cli.add_option("--label", sources.label, "Label of the sessions' views (default: each session's tool_label)"),
      cli.add_option("--images", sources.images, "Text file of \"path label x y w h\" lines (paths relative to it)"),
      cli.add_option("--features-db", sources.features_db, "Feature database DIR/<label>/<n>.txt")};
  toolinc::DnnFeatureConfig dnn;
  std::pair<int, int> input_size{dnn.input_width, dnn.input_height};
  const std::vector<CLI::Option*> dnn_only = {
      cli.add_option("--input-size", input_size, "dnn: network input W H, 1 to 4096 px each (default 224 224)")
          ->capture_default_str(),
      cli.add_option("--mean", dnn.mean, "dnn: per-channel mean r g b of pixel values in [0, 1]")
          ->capture_default_str(),
      cli.add_option("--std", dnn.std, "dnn: per-channel std r g b of pixel values in [0, 1]")->capture_default_str(),
      cli.add_option("--channel-order", dnn.channel_order, "dnn: channel order of the network input (rgb|bgr)")
          ->capture_default_str(),
      cli.add_option("--output-layer", dnn.output_layer,
                     "dnn: layer whose output is the feature (default: the output)")};

  std::string classifier_path, bbox;
  toolinc::ClassifyInput input;
  std::size_t view = 0;
  toolinc::DecisionConfig decision;
  std::vector<CLI::Option*> classify_only = {
      cli.add_option("--classifier", classifier_path, "classify: the classifier JSON"),
      cli.add_option("--view", view, "classify: only this view of the session"),
      cli.add_option("--image", input.image, "classify: an image (with --bbox)"),
      cli.add_option("--bbox", bbox, "classify: the tool's box x,y,w,h in --image (the crop adds 10 px around it)"),
      cli.add_option("--features", input.features, "classify: a file of feature vectors, one per line"),
      cli.add_option("--min-score", decision.min_score,
                     "classify: below this best score the answer is unknown (default: the classifier's)"),
      cli.add_option("--min-margin", decision.min_margin,
                     "classify: closer than this to the second best score the answer is unknown (default: the "
                     "classifier's)"),
      cli.add_option("--max-distance", decision.max_distance,
                     "classify: a whole session whose depth block lies farther than this from every training "
                     "session of its answer is unknown (default: the classifier's)"),
      cli.add_option("--sure-score", decision.sure_score,
                     "classify: a whole session whose best score is above this is its answer however far it lies "
                     "(default: the classifier's)")};

  g_args.assign(argv + 1, argv + argc);
  return command.run(argc, argv, [&] {
    if (action == "train") {
      reject_options(classify_only, "train");
      std::optional<toolinc::DnnFeatureConfig> backbone_config;
      if (!backbone.empty()) {
        dnn.model = backbone;
        std::tie(dnn.input_width, dnn.input_height) = input_size;
        backbone_config = dnn;
      } else {
        reject_options(dnn_only, "train without --backbone");
      }
      toolinc::Json summary;
      const auto classifier = toolinc::train_appearance(sources, backbone_config, {}, summary);
      toolinc::write_json(command.output(), toolinc::classifier_json(classifier, summary));
      return;
    }
    reject_options(train_only, "classify");
    reject_options(dnn_only, "classify (the classifier records the network's settings)");
    if (classifier_path.empty()) throw std::invalid_argument("classify needs --classifier");
    if (sources.sessions.size() > 1) throw std::invalid_argument("classify takes one --session");
    if (!sources.sessions.empty()) input.session = sources.sessions.front();
    if (cli.count("--view")) input.view = view;
    if (!bbox.empty()) input.bbox = toolinc::parse_bbox(bbox);
    const auto classifier = toolinc::read_classifier(classifier_path, backbone);
    toolinc::DecisionConfig thresholds = classifier.decision;
    if (cli.count("--min-score")) thresholds.min_score = decision.min_score;
    if (cli.count("--min-margin")) thresholds.min_margin = decision.min_margin;
    if (cli.count("--max-distance")) thresholds.max_distance = decision.max_distance;
    if (cli.count("--sure-score")) thresholds.sure_score = decision.sure_score;
    const auto result = toolinc::classify_appearance(classifier, classifier_path, input, thresholds);
    spdlog::info("{} (best score {:.3f}, margin {:.3f})", result["label"].get<std::string>(),
                 result["best_score"].get<double>(), result["margin"].get<double>());
    toolinc::write_json(command.output(), result);
  });
}
