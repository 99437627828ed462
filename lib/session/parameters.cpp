#include "toolinc/session/parameters.hpp"

namespace toolinc {

namespace {
constexpr bool kOpen = true, kClosed = false;
using C = CropConfig;
}  // namespace

const std::vector<Parameter<CropConfig>>& crop_parameters() {
  static const std::vector<Parameter<CropConfig>> table{
      {"hand-radius", "m", "Points this close to the hand origin are the hand's", &C::hand_radius, 0, kClosed,
       kMaxLength},
      {"outlier-neighbors", "", "Statistical outlier removal: the neighbours a point's mean distance is taken over",
       &C::outlier_neighbors, 1, kClosed, 1000},
      {"outlier-std", "",
       "Statistical outlier removal: a point whose mean distance exceeds the cloud's by this many deviations is "
       "dropped",
       &C::outlier_std, 0, kOpen, 100},
      {"min-points", "", "Fewer points left is a failure (exit 3)", &C::min_points, 0, kClosed, kMaxCount},
      {"edge-radius", "px", "Mask pixels this close to a depth edge are dropped; 2 suits SFM's SGBM, 0 is off",
       &C::edge_radius_px, 0, kClosed, 100},
      {"edge-jump", "px", "Disparity change per pixel that makes a depth edge", &C::edge_jump_px, 0, kOpen, 1000},
      {"mask-band", "px",
       "With image-mask, how far inside the blob's border the image may trim (the fattening's reach)",
       &nested<C, &C::mask, &ToolMaskConfig::band_px>, 0, kClosed, 1000},
      {"mask-surround", "px", "With image-mask, the background's colours are learnt this far around the blob",
       &nested<C, &C::mask, &ToolMaskConfig::surround_px>, 0, kOpen, 1000},
      {"flood-distance", "m", "With flood, neighbouring points closer than this are connected", &C::flood_distance,
       kMinLength, kClosed, kMaxLength},
  };
  return table;
}

}  // namespace toolinc
