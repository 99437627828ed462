// Where the left eye looks during the exploration (original-method.md sect. 3, lookAtTool and
// get2Dtooltip): first at a guess of the tool's end from the hand pose, then, from the blob, at the point
// 3/4 of the way from the hand to the blob's farthest pixel, a few times at most.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/session/session.hpp"

namespace toolinc {

struct GazeConfig {
  // Hand frame: 16 cm along the hand's X and 16 cm up the tool (hand -Y), the original's guess.
  Vec3 first_guess{0.16, -0.16, 0.0};
  int refine_iterations = 3;      // at most this many re-fixations from the blob (lookAtTool's 3)
  double refine_fraction = 0.75;  // of the way from the projected hand to the blob's farthest pixel
  double tolerance_px = 5.0;      // a target this close to the image centre is fixated already
};

// The first fixation point (root frame) for the hand at root_from_hand.
Vec3 first_fixation(const Eigen::Matrix4d& root_from_hand, const GazeConfig& config);

// The pixel where a root-frame point appears; nothing when it is behind the camera.
std::optional<Eigen::Vector2d> project(const CameraModel& camera, const Eigen::Matrix4d& root_from_camera,
                                       const Vec3& root_point);

// get2Dtooltip: the blob pixel (mask > 0) farthest from hand_pixel, `fraction` of the way from hand_pixel
// to it; nothing when the mask is empty. Ties go to the first pixel in row-major order.
std::optional<Eigen::Vector2d> blob_target(const cv::Mat& mask, const Eigen::Vector2d& hand_pixel, double fraction);

// The root-frame point seen at `pixel` at camera depth `depth` (lookAtMonoPixel's rule).
Vec3 point_at_pixel(const CameraModel& camera, const Eigen::Matrix4d& root_from_camera, const Eigen::Vector2d& pixel,
                    double depth);

}  // namespace toolinc
