// What learn-appearance does, as functions of plain inputs: gather labelled features from sessions,
// image lists and feature databases and train a classifier; classify a session's views, one image box or
// rows of features.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "toolinc/appearance/classifier_file.hpp"
#include "toolinc/appearance/feature_db.hpp"
#include "toolinc/appearance/recognition.hpp"

namespace toolinc {

struct TrainingSources {
  std::vector<std::string> sessions;  // every view's crop, labelled by `label` or else the session's tool_label
  std::string label;
  std::string images;       // a text file of "path label x y w h" lines (paths relative to it)
  std::string features_db;  // DIR/<label>/<n>.txt
};

// The whole of `train`: the extractor is the network when a backbone is given, else the builtin
// descriptor, else (features only) an external one of the database's dimension; features of every
// sample, in source order (sessions, images, database); then the classifier: for the builtin descriptor
// with its image shape blocks (beside depth), then its colour block weighed by leave-one-session-out
// (weigh_block), and, trained on sessions of three
// labels or more, with its unknown floor chosen on the training data (README "Recognising tools by
// appearance", 6.; the defaults otherwise). Throws InputError naming
// the file for unreadable input, a missing or reserved label, a box outside its image, or database
// vectors whose length is not the extractor's; MethodError with fewer than two labels.
// training_summary receives what the classifier file records about the data.
AppearanceClassifier train_appearance(const TrainingSources& sources, const std::optional<DnnFeatureConfig>& backbone,
                                      const RlsConfig& rls, Json& training_summary);

struct ClassifyInput {
  std::string session;
  std::optional<std::size_t> view;
  std::string image;
  std::optional<cv::Rect> bbox;  // the object's box in image; the crop adds the margin
  std::string features;          // a file of feature rows
};

// The classification result (docs/formats.md); exactly one of session, image (with bbox) or features.
// Throws std::invalid_argument on a bad combination, InputError naming the file on bad input (including
// features whose length is not the classifier's, or images given to a classifier of external features).
Json classify_appearance(const AppearanceClassifier& classifier, const std::string& classifier_path,
                         const ClassifyInput& input, const DecisionConfig& decision);

}  // namespace toolinc
