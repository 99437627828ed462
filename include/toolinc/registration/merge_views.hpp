// Merging the exploration views of a tool, all in the hand frame, into one model (paper sect. 3): each
// view is refined against the model built so far by robust ICP (the first view is the reference), and
// a view whose correction is implausible is rejected, with the reason, never silently.
#pragma once

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "toolinc/registration/icp.hpp"

namespace toolinc {

struct MergeConfig {
  IcpConfig icp;
  double voxel_size = 0.002;             // m: the model's grid (the original's 2 mm)
  double registration_voxel = 0.004;     // m: views are resampled this coarsely for ICP (speed; the fit
                                         //    is to the model's 2 mm surface all the same)
  double max_translation = 0.10;         // m per axis: the original's feasibility check
  double max_rotation_deg = 20.0;        // the original checks none, and so accepts flipped views
  double min_inlier_ratio = 0.4;         // share of a view's points that must land on the model
  int min_points = 300;                  // a view with fewer points is rejected (the original's floor)
  double clean_radius = 0.01;            // m: stray points with fewer than clean_min_neighbors within
  int clean_min_neighbors = 20;          //    clean_radius are removed at the end (the original's values)
  bool revisit_views = false;            // a view that does not fit is tried again after the later views,
                                         //    and while one still does not, every view is tried as the
                                         //    reference; off: each view once, the first the reference
                                         //    unless fewer than half the views fit it
  double see_through_tolerance = 0.005;  // m: a view's point that another view saw through, nearer to that
                                         //    view than the tool it saw there by more than this (depth noise
                                         //    and registration residual), is smear and is dropped; 0: none
  // Called after each view with (views done, views in all); none by default. A merge of many views takes
  // minutes, so the executable shows this on a terminal (toolinc/app/progress.hpp).
  std::function<void(std::size_t done, std::size_t total)> progress;
};

struct ViewMerge {
  bool accepted = false;
  std::string reason;                                        // why rejected, or "aligned"
  Eigen::Matrix4d correction = Eigen::Matrix4d::Identity();  // model_from_view found by ICP
  double translation_m[3] = {0, 0, 0};
  double rotation_deg = 0.0;
  double inlier_ratio = 0.0, inlier_rmse = 0.0;
  int iterations = 0;
  int points = 0;
  int smear_dropped = 0;  // of its points, dropped as smear: another view saw through them and none saw them
};

// The model's points say which views saw them (PointCloud::views, a bit each) when it merges at most this
// many views; a model of more carries no view labels.
constexpr std::size_t kMaxLabelledViews = 32;

struct MergeResult {
  PointCloud model;  // in the hand frame estimated as the mean of the accepted views', with the views that
                     // saw each point (at most kMaxLabelledViews views)
  Eigen::Matrix4d hand_from_reference = Eigen::Matrix4d::Identity();  // that frame from the reference view's
  std::vector<ViewMerge> views;
};

// Views in the hand frame, with their viewpoints if known (carried into the model with the corrections).
// The first view is the reference, unless fewer than half the views fit onto it (with revisit_views: unless
// some view fits neither once nor when tried again after the later views): then the view that the most
// others fit, the earliest of equals (with revisit_views, of equals the merge holding the most points).
// The results are in the input's order all the same. Throws MethodError when the first view has fewer than
// min_points points.
MergeResult merge_views(const std::vector<PointCloud>& views, const MergeConfig& config = {});

// The merge of the original exploreTool, which made the robot's reconstructions, for judging the method on
// clouds like them: its ICP (PCL's, from identity) stops on the first step that moves under 1 cm and 0.81
// degrees, so a view stays about where its recorded hand pose put it (here: exactly), every view within its
// 10 cm check is kept, and nothing removes smear.
MergeConfig original_merge();

}  // namespace toolinc
