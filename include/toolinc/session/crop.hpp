// crop-cloud's core: one recorded view -> the tool's points in the hand frame (paper sect. 3,
// original-method.md sect. 1-2).
#pragma once

#include <string>

#include "toolinc/core/point_cloud.hpp"
#include "toolinc/session/blob.hpp"
#include "toolinc/session/session.hpp"
#include "toolinc/session/tool_mask.hpp"

namespace toolinc {

struct CropConfig {
  // The hand-frame box the tool can occupy (inclusive): a tool reaches up to 40 cm from the hand, its
  // head up to 20 cm to either side of the handle's plane (the original's y >= -0.30 m cut the far end
  // of 33-39 cm tools held upright). For the left hand its Z range is mirrored (z -> -z), since the
  // hands' frames are mirror images about the body's midplane.
  Eigen::Vector3d box_min{0.0, -0.40, -0.20};
  Eigen::Vector3d box_max{0.40, 0.0, 0.20};
  double hand_radius = 0.08;  // m: points this close to the hand origin are the hand's (exploration value)
  // m: no part of a held tool lies farther from the hand (the box's length); the tool's silhouette in the
  // image is sought within this ball, whichever way the grasp turns the head.
  double reach = 0.40;
  // m: neighbouring pixels whose 3D points are closer than this lie on one surface, for following the tool
  // out of the hand: two steps of the 8-bit disparity at arm's length (about 5 mm each at 45 cm), far
  // less than the gap between a held tool and the table or wall behind it.
  double surface_step = 0.01;
  int outlier_neighbors = 10;  // statistical outlier removal: k ...
  double outlier_std = 3.0;    // ... and the deviations allowed (the original's k 10, 3 sigma)
  int min_points = 300;        // fewer left is a failure (exit 3)
  // Depth edges: block matching smears the nearer surface's disparity up to half its block past a depth
  // edge (fattening) and leaves pixels between the two depths (flying pixels). A mask pixel is dropped
  // when a pixel within edge_radius_px of it has a disparity lower by more than edge_jump_px per pixel of
  // their distance (a surface at 45 cm seen 85 degrees from frontal changes by 1.7 px per pixel), or
  // none (no match beside a matched pixel is an occlusion or a wrong-match edge). 0 (default) disables:
  // on disparity without fattening it only shaves the tool's true edges, tip included.
  int edge_radius_px = 0;     // px (matched_stereo_crop(sgbm)'s: 2)
  double edge_jump_px = 2.0;  // px of disparity per pixel
  // The blob less what the left image shows to be background at its border (tool_mask.hpp).
  bool image_mask = false;
  ToolMaskConfig mask;
  // A blob that does not reach the hand (none of its pixels' points within hand_radius of it) is joined by
  // the tool followed out of the hand, as view_tool_mask seeds its mask: the closest blob may be a head
  // nearer than its handle, cut off from it at their depth edge. Off (default): the blob alone. A view with
  // no blob at all is cropped to view_tool_mask's part with depth either way.
  bool follow_hand = false;
  bool flood = false;             // grow the region from the blob's centre through 3D continuity
  double flood_distance = 0.004;  // m: neighbouring points closer than this are connected (SFM's Flood3D)
  BlobDetectorConfig blob;        // used when the view has no blob.png
};

struct CropResult {
  PointCloud cloud;           // hand frame, with the left image's colours
  std::string mask_source;    // "blob.png" or "closest blob on the disparity"
  std::string points_source;  // "points.pcd" or "disparity reprojection (approximate)"
  int mask_pixels = 0, edge_pixels = 0, points_3d = 0, in_box = 0, outside_hand = 0;
};

// How the iCub stereo module SFM matched the disparity: LIBELAS (its default) or SGBM (--use_sgbm).
enum class StereoMatcher { libelas, sgbm };

// The settings for disparity matched from the two images, which fattens the tool past its edges: the blob
// trimmed by the left image, and for SGBM depth edges dropped within 2 px as well. SGBM's 7 px blocks
// fatten by up to their half-size, 3 px, beyond what the image's trim reaches in places, but dropping 3 px
// also shaves the true tips (on 96 SGBM sessions the tooltip was within 20 mm in 54 with 0 px, 61 with 2,
// 41 with 3). LIBELAS interpolates between support points instead of spreading a block, the image's trim
// takes its fattening, and dropping depth edges too only shaves the tool's true edges: a bar's far side
// lost that way puts an L-stick's tip 15-17 mm short (on the families' LIBELAS-like sessions, tooltips
// within 10 mm of the aligned truth: 109 of 128 with the 2 px drop, 114 without).
CropConfig matched_stereo_crop(StereoMatcher matcher);

// The view's root-frame point of every pixel (row-major, NaN where there is none): the stereo module's
// exact points where recorded, else reprojected from the 8-bit disparity.
std::vector<Vec3> view_root_points(const CameraModel& camera, const ViewRecord& record, const ViewData& view);

// Whether a hand-frame point lies where a held tool can be, however it is held: beyond the hand's radius
// and within the tool's reach.
bool within_reach(const Vec3& hand_point, const CropConfig& config = {});

// The tool's silhouette in a view's left image (255 on it), for recognition and display. Seeded by the
// pixels whose 3D points are within the tool's reach: those of the blob, when the view has one and they
// meet it (the blob excludes the background; the reach, the hand), else those that a path of neighbours
// less than surface_step apart in 3D joins to the hand's own pixels (3D points within hand_radius; the
// table or a wall within reach is not joined), so a view whose blob detector found nothing is still
// seen. The seed is then grown and trimmed by the left image (tool_mask with grow, config.mask's band and
// surround), the hand's pixels held as background. `with_depth` is the part of the mask whose own 3D
// points are the tool's (the seed it kept): a pixel the image added has the background's disparity, if
// any. Both empty (all zero) when no seed is found.
struct ViewToolMask {
  cv::Mat mask, with_depth;
};
ViewToolMask view_tool_mask(const SessionInfo& session, const ViewRecord& record, const ViewData& view,
                            const CropConfig& config = {});

// Throws MethodError when the mask is empty or fewer than min_points remain.
CropResult crop_view(const SessionInfo& session, const ViewRecord& record, const ViewData& view,
                     const CropConfig& config = {});

// The root-frame point of pixel (u, v) reprojected from an 8-bit disparity value with the camera model
// (NaN when the value is 0). Approximate: the value is quantised to num_disparities / 255 px.
Vec3 reproject_disparity(const CameraModel& camera, const Eigen::Matrix4d& root_from_camera, int u, int v, int value);

}  // namespace toolinc
