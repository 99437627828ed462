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
  // `border` pixels the sensor is taken to have seen empty (the tool's surroundings).
  FreeSpace(const Points& cloud, const Points& viewpoints, double pixel_deg = 1.0, double tolerance = 0.005,
            int border = 20);

  // True when some viewpoint would have seen p: in its view and not behind what it saw by more than the
  // tolerance. Always true without viewpoints (everything counts as seen).
  bool seen(const Vec3& p) const;

 private:
  struct View {
    Vec3 origin;
    Eigen::Matrix3d camera_from_cloud;
    double focal = 0.0;
    int size = 0;
    std::vector<float> depth;  // size x size, +inf where nothing was seen
  };
  bool seen_from(const View& view, const Vec3& p) const;
  std::vector<View> views_;
  double tolerance_;
};

}  // namespace toolinc
