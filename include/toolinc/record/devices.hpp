// What the recorder needs from the robot, as three small interfaces: the arm holding the tool, the gaze
// (head and eyes with the left camera) and the sources (camera, stereo module, blob detector). The YARP
// adapter implements them over the iCub's modules, the simulated backend over the session simulator's
// renderer, and tests with fakes. Calls never block for long: waits and timeouts are the recorder's.
#pragma once

#include <Eigen/Core>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/session/session.hpp"

namespace toolinc {

// The cartesian controller of one arm; poses are root_from_hand (the controller's end-effector frame).
class Arm {
 public:
  virtual ~Arm() = default;
  virtual void go_to(const Eigen::Matrix4d& root_from_hand) = 0;  // starts the move, returns at once
  virtual bool motion_done() = 0;
  virtual Eigen::Matrix4d pose() = 0;    // the current root_from_hand from the kinematics
  virtual void stop() = 0;               // stops any motion now
  virtual std::string name() const = 0;  // for messages: the controller's port or device
};

// The gaze controller with the left camera's model.
class Gaze {
 public:
  virtual ~Gaze() = default;
  virtual void look_at(const Vec3& root_point) = 0;  // starts fixating the point, returns at once
  virtual bool motion_done() = 0;
  virtual Eigen::Matrix4d left_eye_pose() = 0;  // root_from_camera, optical axes (z forward, x right, y down)
  // Intrinsics and image size; num_disparities and baseline are the recorder's to fill in.
  virtual CameraModel intrinsics() = 0;
  virtual void stop() = 0;
  virtual std::string name() const = 0;
};

// The dispBlobber's blob: its mask (255 = blob) and its record (centroid, area and ROI).
struct BlobReading {
  cv::Mat mask;  // CV_8UC1
  BlobInfo info;
};

// A box of pixels as the stereo module's `Rect tlx tly w h step` takes it.
struct SfmRect {
  int tlx = 0, tly = 0, w = 0, h = 0, step = 1;
};

// The streams the recorder reads. Reads are non-blocking: each returns the oldest message that arrived
// after the last drain(), or nothing yet; the recorder polls with its own timeouts.
class Sources {
 public:
  enum class Stream { left, disparity, blob_mask, blob_box, points };
  virtual ~Sources() = default;
  virtual void drain() = 0;                        // forgets everything received so far: the next reads are fresh
  virtual std::optional<cv::Mat> left() = 0;       // CV_8UC3, BGR
  virtual std::optional<cv::Mat> disparity() = 0;  // CV_8UC1, the stereo module's 8-bit disparity
  virtual std::optional<cv::Mat> blob_mask() = 0;  // CV_8UC1
  virtual std::optional<BlobInfo> blob_box() = 0;  // centroid, area and ROI of the same blob
  // The stereo module's root-frame 3D points for the pixels of `rect`, in its order (sfm_rect_pixels):
  // exactly one per pixel, (0, 0, 0) where it has none; nothing when the module did not answer in time.
  virtual std::optional<Points> points(const SfmRect& rect) = 0;
  virtual std::string name(Stream stream) const = 0;  // the port (or stand-in) a stream comes from
};

}  // namespace toolinc
