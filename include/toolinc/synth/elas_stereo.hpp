// An ELAS-style matcher (Geiger, Roser and Urtasun, "Efficient Large-Scale Stereo Matching", ACCV 2010),
// the disparity the iCub stereo module SFM computes by default: robust support points matched on a
// regular grid, a Delaunay triangulation of them whose planes are the prior of a dense per-pixel match,
// then a left-right check, speckle removal, gap interpolation and an adaptive mean filter. The defaults
// are LIBELAS's ROBOTICS setting with SFM's overrides (StereoCamera::initELAS and elasWrapper in
// robotology/stereo-vision): ipol_gap_width 40, postprocess_only_left, disp_max = 95 at 320 px.
#pragma once

#include <opencv2/core.hpp>

namespace toolinc {

struct ElasConfig {
  int disp_max = 95;                 // px; SFM: numberOfDisparities - 1 (96 at width <= 320)
  double support_threshold = 0.85;   // a support match's best cost below this share of the second best
  int support_texture = 10;          // sum of |descriptor - 128| a support point needs
  int candidate_stepsize = 5;        // px between support candidates
  int incon_window_size = 5;         // candidates around a support point that are asked ...
  int incon_threshold = 5;           // ... whether they agree within this disparity ...
  int incon_min_support = 5;         // ... and how many must
  int grid_size = 20;                // px: cells whose support disparities (+/- 1, dilated) every pixel tries
  double beta = 0.02;                // image likelihood: cost units per nat
  double gamma = 3;                  // prior: weight of the uniform part against the plane's Gaussian
  double sigma = 1;                  // px, the plane prior's Gaussian
  double sradius = 2;                // sigmas of the window searched around the plane
  int match_texture = 1;             // sum of |descriptor - 128| a pixel needs to be matched densely
  int lr_threshold = 2;              // px, left-right consistency
  double speckle_sim_threshold = 1;  // px between neighbours of one segment
  int speckle_size = 200;            // px, segments smaller than this are removed
  int ipol_gap_width = 40;           // px, gaps up to this wide are filled along rows and columns
  bool filter_adaptive_mean = true;  // the approximate bilateral filter over 8 px
};

// Disparity of the left image of a rectified pair (8-bit grey or 3-channel BGR, converted to grey as
// SFM's wrapper does): CV_32FC1, negative where there is none.
cv::Mat elas_disparity(const cv::Mat& left, const cv::Mat& right, const ElasConfig& config = {});

// The same as SFM keeps it for its 3D points (Disparity16): 16 x disparity, CV_16SC1, negative where invalid.
cv::Mat elas_disparity16(const cv::Mat& left, const cv::Mat& right, const ElasConfig& config = {});

}  // namespace toolinc
