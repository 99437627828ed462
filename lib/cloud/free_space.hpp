// What the sensors saw as empty. A merged model is seen only from the exploration viewpoints, so the far
// side of a tool is often missing; a mirror image landing there is no evidence against a symmetry
// plane, whereas one landing where a sensor looked and saw nothing is.
#pragma once

#include <vector>

#include "toolinc/core/point_cloud.hpp"

namespace toolinc {

class FreeSpace {
 public:
  // One depth image of `cloud` per viewpoint (same frame), `pixel_deg` wide pixels, plus a border of
  // `border` pixels the sensor is taken to have seen empty (the tool's surroundings). A sensor sees at
  // most `max_half_angle_deg` off the direction to the cloud's centroid (a camera's half field of view,
  // generous for the iCub's eyes): this bounds each image (at most 2 x (57 x tan 60 + 20) + 1 = 241
  // pixels wide by default), whatever a viewpoint inside or beside the cloud would ask for. A viewpoint
  // that is not finite or sits on the centroid has no direction and is left out.
  FreeSpace(const Points& cloud, const Points& viewpoints, double pixel_deg = 1.0, double tolerance = 0.005,
            int border = 20, double max_half_angle_deg = 60.0);

  // True when some viewpoint would have seen p: in its view and not behind what it saw by more than the
  // tolerance. Always true without viewpoints (everything counts as seen).
  bool seen(const Vec3& p) const;

  // True when some viewpoint looked through p: in its view, nearer to it by more than the tolerance than
  // anything it saw there. A point another sensor saw through is not on the tool: smear strung along
  // the first sensor's ray. False without viewpoints.
  bool seen_through(const Vec3& p) const;

  std::size_t views() const { return views_.size(); }  // viewpoints used
  std::size_t pixels() const;                          // over all depth images: their memory, in floats

 private:
  struct View {
    Vec3 origin;
    Eigen::Matrix3d camera_from_cloud;
    double focal = 0.0;
    int size = 0;
    std::vector<float> depth;  // size x size, +inf where nothing was seen
  };
  // The depth of p along the view's axis and the nearest depth the view saw around p's pixel (+inf where
  // it saw nothing); false when p is off the view's image.
  bool depths(const View& view, const Vec3& p, double& depth, double& nearest) const;
  static bool pixel(const View& view, const Vec3& q, int& u, int& v);
  std::vector<View> views_;
  double tolerance_;
};

}  // namespace toolinc
