// Each building block of the pipeline beside the same block of the libraries a researcher would otherwise
// use (nanoflann, PCL, Open3D), in one process, on the same clouds, on one core. Per row: the median time
// of repeated runs, its ratio to the fastest peer, and what the block produced (answers, points kept,
// final error), so that times are compared at equal results. A peer that is not installed is left out.
// Where no peer does a whole job (align-pose, merge-views), the composition of its blocks a researcher
// would make is the baseline, and what each produced is measured against the truth.
//
//   build/bench/bench_peers [SECONDS]   (each block repeated for about SECONDS, 0.5 by default; the peers'
//                                        OpenMP is held to one thread by the program itself)
#include <sys/resource.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <numeric>
#include <string>
#include <type_traits>
#include <vector>

#include "toolinc/ann/kdtree.hpp"
#include "toolinc/ann/nearest_distance.hpp"
#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/core/random.hpp"
#include "toolinc/frame/tool_frame.hpp"
#include "toolinc/frame/tooltip.hpp"
#include "toolinc/registration/align_pose.hpp"
#include "toolinc/registration/icp.hpp"
#include "toolinc/registration/merge_views.hpp"
#include "toolinc/session/crop.hpp"
#include "toolinc/synth/evaluation.hpp"
#include "toolinc/synth/partial_view.hpp"
#include "toolinc/synth/session_simulator.hpp"

#ifdef TOOLINC_WITH_NANOFLANN
#include <nanoflann.hpp>
#endif
#ifdef TOOLINC_WITH_PCL
#include <pcl/common/io.h>
#include <pcl/features/fpfh.h>
#include <pcl/features/normal_3d.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl/registration/icp.h>
#include <pcl/registration/sample_consensus_prerejective.h>

#include "pcl_cloud.hpp"
#endif
#ifdef TOOLINC_WITH_OPEN3D
#include <open3d/geometry/KDTreeFlann.h>
#include <open3d/geometry/PointCloud.h>
#include <open3d/pipelines/registration/CorrespondenceChecker.h>
#include <open3d/pipelines/registration/Feature.h>
#include <open3d/pipelines/registration/Registration.h>
#include <open3d/pipelines/registration/TransformationEstimation.h>
#include <open3d/utility/Random.h>
#endif
#ifdef _OPENMP
#include <omp.h>
#endif

using namespace toolinc;

namespace {

constexpr int kNeighbours = 10;           // k of the k-NN queries, of normals and of the outlier filter
constexpr double kRadius = 0.01;          // m: radius queries (the density checks' radius)
constexpr double kVoxel = 0.004;          // m: the tool frame's resampling
constexpr double kOutlierStd = 3.0;       // crop-cloud's statistical outlier filter
constexpr double kCorrespondence = 0.02;  // m: ICP's correspondence radius (toolinc's default)

double min_time_ms = 500.0;

// Median wall time of fn in ms: repeated until min_time_ms have passed (at least 3, at most 200 runs).
double median_ms(const std::function<void()>& fn) {
  std::vector<double> times;
  double total = 0.0;
  while (times.size() < 3 || (total < min_time_ms && times.size() < 200)) {
    const auto start = std::chrono::steady_clock::now();
    fn();
    const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    times.push_back(ms);
    total += ms;
  }
  std::nth_element(times.begin(), times.begin() + times.size() / 2, times.end());
  return times[times.size() / 2];
}

struct Row {
  std::string library;
  double ms;
  std::string result;
};

// One block's rows, toolinc first, with each time's ratio to the fastest peer's.
void print_block(const std::string& block, const std::vector<Row>& rows) {
  double fastest_peer = 0.0;
  for (std::size_t i = 1; i < rows.size(); ++i)
    fastest_peer = fastest_peer == 0.0 ? rows[i].ms : std::min(fastest_peer, rows[i].ms);
  std::printf("\n%s\n", block.c_str());
  for (const auto& row : rows) {
    const std::string ratio = fastest_peer > 0 ? std::to_string(row.ms / fastest_peer).substr(0, 4) : "-";
    std::printf("  %-10s %9.3f ms  x%-5s  %s\n", row.library.c_str(), row.ms, ratio.c_str(), row.result.c_str());
  }
}

#ifdef TOOLINC_WITH_PCL
// A PCL cloud with PCL's normals: from the k nearest points, or from those within `radius` when positive.
pcl::PointCloud<pcl::PointNormal>::Ptr pcl_with_normals(const pcl::PointCloud<pcl::PointXYZ>::Ptr& xyz, int k,
                                                        double radius = 0.0) {
  pcl::NormalEstimation<pcl::PointXYZ, pcl::Normal> estimation;
  estimation.setInputCloud(xyz);
  if (radius > 0.0)
    estimation.setRadiusSearch(radius);
  else
    estimation.setKSearch(k);
  pcl::PointCloud<pcl::Normal> normals;
  estimation.compute(normals);
  pcl::PointCloud<pcl::PointNormal>::Ptr cloud(new pcl::PointCloud<pcl::PointNormal>);
  for (std::size_t i = 0; i < xyz->size(); ++i) {
    pcl::PointNormal p;
    p.getVector3fMap() = (*xyz)[i].getVector3fMap();
    p.getNormalVector3fMap() = normals[i].getNormalVector3fMap();
    cloud->push_back(p);
  }
  return cloud;
}
#endif

#ifdef TOOLINC_WITH_NANOFLANN
struct NanoCloud {
  const Points& points;
  std::size_t kdtree_get_point_count() const { return points.size(); }
  double kdtree_get_pt(std::size_t i, std::size_t d) const { return points[i][static_cast<int>(d)]; }
  template <class Box>
  bool kdtree_get_bbox(Box&) const {
    return false;
  }
};
using NanoTree =
    nanoflann::KDTreeSingleIndexAdaptor<nanoflann::L2_Simple_Adaptor<double, NanoCloud>, NanoCloud, 3, std::uint32_t>;
#endif

#ifdef TOOLINC_WITH_OPEN3D
open3d::geometry::PointCloud to_open3d(const Points& points) {
  open3d::geometry::PointCloud cloud;
  cloud.points_.assign(points.begin(), points.end());
  return cloud;
}
#endif

// Neighbour search on one cloud: building the index, k-NN of every point, and counting every point's
// neighbours within kRadius. The checksums (sum of k-NN distances, sum of counts) show equal answers.
void neighbour_search(const std::string& name, const Points& points) {
  std::vector<Row> build, knn, radius;
  {
    build.push_back({"toolinc", median_ms([&] { const KdTree tree(points); }), ""});
    const KdTree tree(points);
    double sum = 0.0;
    KNearest nearest(kNeighbours);  // as the peers' result buffers, allocated once
    knn.push_back({"toolinc", median_ms([&] {
                     sum = 0.0;
                     for (const auto& p : points) {
                       tree.knn(p, nearest);
                       for (const auto& n : nearest.kept()) sum += std::sqrt(n.distance2);
                     }
                   }),
                   ""});
    knn.back().result = "sum of distances " + std::to_string(sum);
    std::size_t count = 0;
    radius.push_back({"toolinc", median_ms([&] {
                        count = 0;
                        for (const auto& p : points) count += tree.count_within(p, kRadius);
                      }),
                      ""});
    radius.back().result = "neighbours " + std::to_string(count);
  }
#ifdef TOOLINC_WITH_NANOFLANN
  {
    const NanoCloud cloud{points};
    build.push_back({"nanoflann", median_ms([&] {
                       NanoTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(12));
                       tree.buildIndex();
                     }),
                     ""});
    NanoTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(12));
    tree.buildIndex();
    double sum = 0.0;
    std::vector<std::uint32_t> indices(kNeighbours);
    std::vector<double> distances(kNeighbours);
    knn.push_back({"nanoflann", median_ms([&] {
                     sum = 0.0;
                     for (const auto& p : points) {
                       const std::size_t found =
                           tree.knnSearch(p.data(), kNeighbours, indices.data(), distances.data());
                       for (std::size_t j = 0; j < found; ++j) sum += std::sqrt(distances[j]);
                     }
                   }),
                   ""});
    knn.back().result = "sum of distances " + std::to_string(sum);
    std::size_t count = 0;
    std::vector<std::pair<std::uint32_t, double>> matches;
    const nanoflann::SearchParams unsorted(32, 0.0, false);  // the neighbours' order is not needed
    radius.push_back({"nanoflann", median_ms([&] {
                        count = 0;
                        for (const auto& p : points)
                          count += tree.radiusSearch(p.data(), kRadius * kRadius, matches, unsorted);
                      }),
                      ""});
    radius.back().result = "neighbours " + std::to_string(count);
  }
#endif
#ifdef TOOLINC_WITH_PCL
  {
    const auto cloud = to_pcl(points);
    build.push_back({"PCL", median_ms([&] {
                       pcl::KdTreeFLANN<pcl::PointXYZ> tree;
                       tree.setInputCloud(cloud);
                     }),
                     ""});
    pcl::KdTreeFLANN<pcl::PointXYZ> tree;
    tree.setInputCloud(cloud);
    double sum = 0.0;
    std::vector<int> indices;
    std::vector<float> distances;
    knn.push_back({"PCL", median_ms([&] {
                     sum = 0.0;
                     for (const auto& p : *cloud) {
                       tree.nearestKSearch(p, kNeighbours, indices, distances);
                       for (const float d : distances) sum += std::sqrt(static_cast<double>(d));
                     }
                   }),
                   ""});
    knn.back().result = "sum of distances " + std::to_string(sum);
    std::size_t count = 0;
    radius.push_back({"PCL", median_ms([&] {
                        count = 0;
                        for (const auto& p : *cloud)
                          count += static_cast<std::size_t>(tree.radiusSearch(p, kRadius, indices, distances));
                      }),
                      ""});
    radius.back().result = "neighbours " + std::to_string(count);
  }
#endif
#ifdef TOOLINC_WITH_OPEN3D
  {
    const auto cloud = to_open3d(points);
    build.push_back({"Open3D", median_ms([&] { const open3d::geometry::KDTreeFlann tree(cloud); }), ""});
    const open3d::geometry::KDTreeFlann tree(cloud);
    double sum = 0.0;
    std::vector<int> indices;
    std::vector<double> distances;
    knn.push_back({"Open3D", median_ms([&] {
                     sum = 0.0;
                     for (const auto& p : points) {
                       tree.SearchKNN(p, kNeighbours, indices, distances);
                       for (const double d : distances) sum += std::sqrt(d);
                     }
                   }),
                   ""});
    knn.back().result = "sum of distances " + std::to_string(sum);
    std::size_t count = 0;
    radius.push_back({"Open3D", median_ms([&] {
                        count = 0;
                        for (const auto& p : points)
                          count += static_cast<std::size_t>(tree.SearchRadius(p, kRadius, indices, distances));
                      }),
                      ""});
    radius.back().result = "neighbours " + std::to_string(count);
  }
#endif
  const std::string of = " (" + name + ", " + std::to_string(points.size()) + " points)";
  print_block("kd-tree build" + of, build);
  print_block("k-NN, k = " + std::to_string(kNeighbours) + ", every point" + of, knn);
  print_block("neighbours within 10 mm, every point" + of, radius);
}

// Voxel downsampling and statistical outlier removal of one cloud; the points each keeps.
void filters(const std::string& name, const Points& points) {
  std::vector<Row> voxel, outliers;
  std::size_t kept = 0;
  voxel.push_back({"toolinc", median_ms([&] { kept = voxel_downsample(points, kVoxel).size(); }), ""});
  voxel.back().result = std::to_string(kept) + " points";
  outliers.push_back(
      {"toolinc", median_ms([&] { kept = statistical_inliers(points, kNeighbours, kOutlierStd).size(); }), ""});
  outliers.back().result = std::to_string(kept) + " kept";
#ifdef TOOLINC_WITH_PCL
  {
    const auto cloud = to_pcl(points);
    pcl::PointCloud<pcl::PointXYZ> out;
    voxel.push_back({"PCL", median_ms([&] {
                       pcl::VoxelGrid<pcl::PointXYZ> grid;
                       grid.setInputCloud(cloud);
                       grid.setLeafSize(static_cast<float>(kVoxel), static_cast<float>(kVoxel),
                                        static_cast<float>(kVoxel));
                       grid.filter(out);
                     }),
                     ""});
    voxel.back().result = std::to_string(out.size()) + " points";
    outliers.push_back({"PCL", median_ms([&] {
                          pcl::StatisticalOutlierRemoval<pcl::PointXYZ> filter;
                          filter.setInputCloud(cloud);
                          filter.setMeanK(kNeighbours);
                          filter.setStddevMulThresh(kOutlierStd);
                          filter.filter(out);
                        }),
                        ""});
    outliers.back().result = std::to_string(out.size()) + " kept";
  }
#endif
#ifdef TOOLINC_WITH_OPEN3D
  {
    const auto cloud = to_open3d(points);
    voxel.push_back({"Open3D", median_ms([&] { kept = cloud.VoxelDownSample(kVoxel)->points_.size(); }), ""});
    voxel.back().result = std::to_string(kept) + " points";
    // Open3D counts the point itself among its neighbours: one more for the same ten as the others.
    outliers.push_back(
        {"Open3D", median_ms([&] {
           kept = std::get<0>(cloud.RemoveStatisticalOutliers(kNeighbours + 1, kOutlierStd))->points_.size();
         }),
         ""});
    outliers.back().result = std::to_string(kept) + " kept";
  }
#endif
  const std::string of = " (" + name + ", " + std::to_string(points.size()) + " points)";
  print_block("voxel downsampling, 4 mm" + of, voxel);
  print_block("statistical outlier removal, k = 10, 3 std" + of, outliers);
}

// RMS distance, over the view's points, between where a transform and the truth put them: the final error.
double rms_error_mm(const Points& view, const Eigen::Matrix4d& estimate, const Eigen::Matrix4d& truth) {
  double sum = 0.0;
  for (const auto& p : view) {
    const Vec3 a = estimate.topLeftCorner<3, 3>() * p + estimate.topRightCorner<3, 1>();
    const Vec3 b = truth.topLeftCorner<3, 3>() * p + truth.topRightCorner<3, 1>();
    sum += (a - b).squaredNorm();
  }
  return 1000.0 * std::sqrt(sum / static_cast<double>(view.size()));
}

// ICP of a partial view onto a held tool's model from 3 degrees and 5 mm off, preparation of the target
// (normals, index) included, as each library needs it. The final error is against the true pose.
void icp(const Points& model, const Points& view, const Eigen::Matrix4d& truth, const Eigen::Matrix4d& start) {
  std::vector<Row> point_to_plane, point_to_point;
  const auto error_text = [&](const Eigen::Matrix4d& estimate) {
    char text[64];
    std::snprintf(text, sizeof text, "final error %.2f mm RMS (start %.2f)", rms_error_mm(view, estimate, truth),
                  rms_error_mm(view, start, truth));
    return std::string(text);
  };
  Eigen::Matrix4d estimate = start;
  point_to_plane.push_back({"toolinc", median_ms([&] {
                              const IcpTarget target(model, kNeighbours);
                              estimate = align_point_to_plane(view, target, start).target_from_source;
                            }),
                            ""});
  point_to_plane.back().result = error_text(estimate);
  point_to_point.push_back({"toolinc", point_to_plane.back().ms, "point-to-plane: " + point_to_plane.back().result});
#ifdef TOOLINC_WITH_PCL
  {
    const auto source = pcl_with_normals(to_pcl(view), kNeighbours);
    // Run to convergence as toolinc does: stopped by 50 iterations or a negligible step.
    const auto run = [&](auto& solver, const auto& source_cloud, const auto& target_cloud) {
      solver.setInputSource(source_cloud);
      solver.setInputTarget(target_cloud);
      solver.setMaxCorrespondenceDistance(kCorrespondence);
      solver.setMaximumIterations(50);
      solver.setTransformationEpsilon(1e-10);
      solver.setEuclideanFitnessEpsilon(1e-12);
      typename std::remove_reference_t<decltype(*source_cloud)> aligned;
      solver.align(aligned, Eigen::Matrix4f(start.cast<float>()));
      estimate = solver.getFinalTransformation().template cast<double>();
    };
    point_to_plane.push_back({"PCL", median_ms([&] {
                                pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal> solver;
                                run(solver, source, pcl_with_normals(to_pcl(model), kNeighbours));
                              }),
                              ""});
    point_to_plane.back().result = error_text(estimate);
    const auto source_xyz = to_pcl(view), target_xyz = to_pcl(model);
    point_to_point.push_back({"PCL", median_ms([&] {
                                pcl::IterativeClosestPoint<pcl::PointXYZ, pcl::PointXYZ> solver;
                                run(solver, source_xyz, target_xyz);
                              }),
                              ""});
    point_to_point.back().result = error_text(estimate);
  }
#endif
#ifdef TOOLINC_WITH_OPEN3D
  {
    namespace reg = open3d::pipelines::registration;
    const auto source = to_open3d(view);
    const reg::ICPConvergenceCriteria until(1e-8, 1e-8, 50);
    point_to_plane.push_back({"Open3D", median_ms([&] {
                                auto target = to_open3d(model);
                                target.EstimateNormals(open3d::geometry::KDTreeSearchParamKNN(kNeighbours));
                                estimate = reg::RegistrationICP(source, target, kCorrespondence, start,
                                                                reg::TransformationEstimationPointToPlane(), until)
                                               .transformation_;
                              }),
                              ""});
    point_to_plane.back().result = error_text(estimate);
    const auto target = to_open3d(model);
    point_to_point.push_back({"Open3D", median_ms([&] {
                                estimate = reg::RegistrationICP(source, target, kCorrespondence, start,
                                                                reg::TransformationEstimationPointToPoint(), until)
                                               .transformation_;
                              }),
                              ""});
    point_to_point.back().result = error_text(estimate);
  }
#endif
  const std::string of =
      " (" + std::to_string(view.size()) + "-point view onto a " + std::to_string(model.size()) + "-point model)";
  print_block("ICP point-to-plane, target preparation included" + of, point_to_plane);
  print_block("ICP point-to-point" + of, point_to_point);
}

// The whole align-pose: a partial view of a held tool onto its model from no initial guess, on the same
// random grasps as bench_align_pose's summary. No peer does the whole job, so the baseline is the
// composition each library's tutorials give for it: features (FPFH on a voxel grid), a RANSAC over
// feature matches (Open3D's RegistrationRANSACBasedOnFeatureMatching, PCL's SampleConsensusPrerejective),
// then point-to-plane ICP. Per library: median and 90th percentile time (model preparation included), and
// the cases within 3 deg, 5 mm and a tooltip within 10 mm of the truth (modulo the tool's symmetry).
constexpr double kFeatureVoxel = 0.005;  // m: the tools' features' grid (a tenth of a head's width)
void whole_align_pose(int per_family) {
  struct Outcome {
    std::vector<double> ms;
    int right = 0;
  };
  std::vector<std::pair<std::string, Outcome>> rows;
  const auto run = [&](const std::string& library,
                       const std::function<Eigen::Matrix4d(const PartialViewCase&)>& align) {
    Outcome outcome;
    for (const ToolFamily family : all_families())
      for (int seed = 0; seed < per_family; ++seed) {
        const PartialViewCase c = make_partial_view_case(family, static_cast<std::uint32_t>(seed));
        const auto start = std::chrono::steady_clock::now();
        const Eigen::Matrix4d hand_from_model = align(c);
        outcome.ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
        outcome.right += pose_errors(c, hand_from_model).within(3.0, 0.005, 0.010);
      }
    rows.emplace_back(library, std::move(outcome));
  };
  run("toolinc",
      [](const PartialViewCase& c) { return align_pose(PoseModel(c.model.points), c.view).best.hand_from_model; });
#ifdef TOOLINC_WITH_OPEN3D
  {
    namespace reg = open3d::pipelines::registration;
    open3d::utility::random::Seed(1);
    const auto prepared = [](const Points& points) {
      auto cloud = to_open3d(points).VoxelDownSample(kFeatureVoxel);
      cloud->EstimateNormals(open3d::geometry::KDTreeSearchParamHybrid(2 * kFeatureVoxel, 30));
      auto features =
          reg::ComputeFPFHFeature(*cloud, open3d::geometry::KDTreeSearchParamHybrid(5 * kFeatureVoxel, 100));
      return std::make_pair(cloud, features);
    };
    run("Open3D", [&](const PartialViewCase& c) {
      const auto [view, view_features] = prepared(c.view);
      const auto [model, model_features] = prepared(c.model.points);
      const reg::CorrespondenceCheckerBasedOnEdgeLength edges(0.9);
      const reg::CorrespondenceCheckerBasedOnDistance distance(1.5 * kFeatureVoxel);
      const auto coarse = reg::RegistrationRANSACBasedOnFeatureMatching(
          *view, *model, *view_features, *model_features, false, 1.5 * kFeatureVoxel,
          reg::TransformationEstimationPointToPoint(false), 3, {edges, distance},
          reg::RANSACConvergenceCriteria(100000, 0.999));
      const auto fine = reg::RegistrationICP(*view, *model, kCorrespondence, coarse.transformation_,
                                             reg::TransformationEstimationPointToPlane(),
                                             reg::ICPConvergenceCriteria(1e-8, 1e-8, 50));
      return Eigen::Matrix4d(fine.transformation_.inverse());  // model_from_view -> hand_from_model
    });
  }
#endif
#ifdef TOOLINC_WITH_PCL
  {
    using Cloud = pcl::PointCloud<pcl::PointNormal>;
    using Features = pcl::PointCloud<pcl::FPFHSignature33>;
    const auto prepared = [](const Points& points) {
      pcl::VoxelGrid<pcl::PointXYZ> grid;
      grid.setInputCloud(to_pcl(points));
      const float leaf = static_cast<float>(kFeatureVoxel);
      grid.setLeafSize(leaf, leaf, leaf);
      pcl::PointCloud<pcl::PointXYZ>::Ptr xyz(new pcl::PointCloud<pcl::PointXYZ>);
      grid.filter(*xyz);
      const auto cloud = pcl_with_normals(xyz, 0, 2 * kFeatureVoxel);
      pcl::FPFHEstimation<pcl::PointNormal, pcl::PointNormal, pcl::FPFHSignature33> fpfh;
      fpfh.setInputCloud(cloud);
      fpfh.setInputNormals(cloud);
      fpfh.setRadiusSearch(5 * kFeatureVoxel);
      Features::Ptr features(new Features);
      fpfh.compute(*features);
      return std::make_pair(cloud, features);
    };
    run("PCL", [&](const PartialViewCase& c) {
      const auto [view, view_features] = prepared(c.view);
      const auto [model, model_features] = prepared(c.model.points);
      pcl::SampleConsensusPrerejective<pcl::PointNormal, pcl::PointNormal, pcl::FPFHSignature33> coarse;
      coarse.setInputSource(view);
      coarse.setSourceFeatures(view_features);
      coarse.setInputTarget(model);
      coarse.setTargetFeatures(model_features);
      coarse.setMaximumIterations(50000);
      coarse.setNumberOfSamples(3);
      coarse.setCorrespondenceRandomness(5);
      coarse.setSimilarityThreshold(0.9f);
      coarse.setMaxCorrespondenceDistance(static_cast<float>(1.5 * kFeatureVoxel));
      coarse.setInlierFraction(0.25f);
      Cloud aligned;
      coarse.align(aligned);
      pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal> fine;
      fine.setInputSource(view);
      fine.setInputTarget(model);
      fine.setMaxCorrespondenceDistance(kCorrespondence);
      fine.setMaximumIterations(50);
      fine.setTransformationEpsilon(1e-10);
      fine.align(aligned, coarse.getFinalTransformation());
      return Eigen::Matrix4d(fine.getFinalTransformation().cast<double>().inverse());
    });
  }
#endif
  std::vector<Row> printed;
  for (auto& [library, o] : rows) {
    std::sort(o.ms.begin(), o.ms.end());
    char text[96];
    std::snprintf(text, sizeof text, "90th percentile %.0f ms; within 3 deg, 5 mm, tooltip 10 mm: %d of %zu",
                  o.ms[o.ms.size() * 9 / 10], o.right, o.ms.size());
    printed.push_back({library, o.ms[o.ms.size() / 2], text});
  }
  print_block("whole align-pose from no initial guess (" + std::to_string(8 * per_family) +
                  " random grasps of the 8 families; peers: FPFH, RANSAC, point-to-plane ICP)",
              printed);
}

// A simulated session of the robot's stereo (a family's tool, one recorded grasp): its views cropped, in
// the hand frame at their recorded poses, and the tool's true surface there.
struct SessionViews {
  std::vector<PointCloud> views;
  Points truth;
};
SessionViews session_views(ToolFamily family, std::uint32_t seed) {
  const SessionSimulatorConfig config = family_session(family, seed);
  const SimulatedSession session = simulate_session(config);
  SessionViews out;
  for (std::size_t v = 0; v < session.views.size(); ++v) {
    try {
      out.views.push_back(
          crop_view(session.info, session.info.views[v], session.views[v], session_crop(StereoModel::elas)).cloud);
    } catch (const MethodError&) {
    }
  }
  out.truth = transform_points(true_surface(config), config.hand_from_canonical);
  return out;
}

// The whole merge-views: five cropped views into one model. No peer does the whole job, so the baseline
// is the composition a researcher would make of the peer's blocks: each view registered onto the first by
// point-to-plane ICP from its recorded pose, the views concatenated, resampled on merge-views' 2 mm grid
// and cleaned by the statistical outlier filter. Per library: median time over the sessions, and the
// merged model's median distance from the true surface (the median over the sessions) and its share of
// points beyond 5 mm of it.
constexpr double kMergeVoxel = 0.002;  // m: merge-views' output grid
void whole_merge_views(int per_family) {
  std::vector<SessionViews> sessions;
  for (const ToolFamily family : all_families())
    for (int seed = 0; seed < per_family; ++seed) sessions.push_back(session_views(family, 100u + seed));
  std::vector<Row> rows;
  const auto run = [&](const std::string& library, const std::function<Points(const std::vector<PointCloud>&)>& merge) {
    std::vector<double> ms, median, beyond;
    for (const auto& s : sessions) {
      Points model;
      ms.push_back(median_ms([&] { model = merge(s.views); }));
      const DistanceProfile profile = distance_profile(model, s.truth);
      median.push_back(1000 * profile.median_m), beyond.push_back(100 * profile.beyond);
    }
    const auto middle = [](std::vector<double> v) {
      std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
      return v[v.size() / 2];
    };
    char text[96];
    std::snprintf(text, sizeof text, "from the true surface: median %.2f mm, %.1f %% beyond 5 mm", middle(median),
                  middle(beyond));
    rows.push_back({library, middle(ms), text});
  };
  run("toolinc", [](const std::vector<PointCloud>& views) { return merge_views(views).model.points; });
#ifdef TOOLINC_WITH_OPEN3D
  run("Open3D", [](const std::vector<PointCloud>& views) {
    namespace reg = open3d::pipelines::registration;
    auto reference = to_open3d(views.front().points);
    reference.EstimateNormals(open3d::geometry::KDTreeSearchParamKNN(kNeighbours));
    open3d::geometry::PointCloud merged = reference;
    for (std::size_t v = 1; v < views.size(); ++v) {
      auto view = to_open3d(views[v].points);
      view.Transform(reg::RegistrationICP(view, reference, kCorrespondence, Eigen::Matrix4d::Identity(),
                                          reg::TransformationEstimationPointToPlane(),
                                          reg::ICPConvergenceCriteria(1e-8, 1e-8, 50))
                         .transformation_);
      merged += view;
    }
    const auto resampled = merged.VoxelDownSample(kMergeVoxel);
    return std::get<0>(resampled->RemoveStatisticalOutliers(kNeighbours + 1, kOutlierStd))->points_;
  });
#endif
#ifdef TOOLINC_WITH_PCL
  run("PCL", [](const std::vector<PointCloud>& views) {
    const auto reference = pcl_with_normals(to_pcl(views.front().points), kNeighbours);
    pcl::PointCloud<pcl::PointXYZ>::Ptr merged(new pcl::PointCloud<pcl::PointXYZ>);
    pcl::copyPointCloud(*reference, *merged);
    for (std::size_t v = 1; v < views.size(); ++v) {
      pcl::IterativeClosestPointWithNormals<pcl::PointNormal, pcl::PointNormal> icp;
      icp.setInputSource(pcl_with_normals(to_pcl(views[v].points), kNeighbours));
      icp.setInputTarget(reference);
      icp.setMaxCorrespondenceDistance(kCorrespondence);
      icp.setMaximumIterations(50);
      icp.setTransformationEpsilon(1e-10);
      pcl::PointCloud<pcl::PointNormal> aligned;
      icp.align(aligned);
      pcl::PointCloud<pcl::PointXYZ> xyz;
      pcl::copyPointCloud(aligned, xyz);
      *merged += xyz;
    }
    pcl::VoxelGrid<pcl::PointXYZ> grid;
    grid.setInputCloud(merged);
    const float leaf = static_cast<float>(kMergeVoxel);
    grid.setLeafSize(leaf, leaf, leaf);
    pcl::PointCloud<pcl::PointXYZ>::Ptr resampled(new pcl::PointCloud<pcl::PointXYZ>);
    grid.filter(*resampled);
    pcl::StatisticalOutlierRemoval<pcl::PointXYZ> filter;
    filter.setInputCloud(resampled);
    filter.setMeanK(kNeighbours);
    filter.setStddevMulThresh(kOutlierStd);
    pcl::PointCloud<pcl::PointXYZ> cleaned;
    filter.filter(cleaned);
    Points out;
    for (const auto& p : cleaned) out.emplace_back(p.x, p.y, p.z);
    return out;
  });
#endif
  print_block("whole merge-views, five views of the robot's stereo (" + std::to_string(sessions.size()) +
                  " sessions of the families; median over them)",
              rows);
}

// n points drawn from a cloud's points, each moved by Gaussian noise of 1 mm per coordinate: the same
// surface, sampled n times.
Points densified(const Points& points, std::size_t n, Rng& rng) {
  Points out(n);
  for (auto& p : out)
    p = points[rng.index(static_cast<std::uint32_t>(points.size()))] +
        0.001 * Vec3(rng.gaussian(), rng.gaussian(), rng.gaussian());
  return out;
}

// Peak resident memory of the process so far, MB.
double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

// Time of estimate-frame + find-tooltip, merge-views of five views and align-pose from 3k to 1M points,
// and the exponent of a power law fitted to the times from 10k points up (below, fixed costs dominate).
void scaling(const SessionSimulatorConfig& scene, std::size_t largest) {
  Rng rng(5);
  std::vector<Points> views;
  for (const auto& wrist : scene.poses) {
    PartialViewConfig config;
    config.wrist_deg = wrist;
    views.push_back(render_partial_view(scene, config, rng));
  }
  const Points& held = views.front();
  const PoseModel model(generate_tool(scene.shape, 1).points);
  std::printf("\nscaling (one core; the process's peak memory after each size)\n");
  std::printf("  %9s  %14s  %16s  %14s  %8s\n", "points", "frame+tooltip", "merge 5 views", "align-pose", "peak MB");
  std::vector<double> log_n, log_time[3];
  std::size_t last = 0;
  for (const std::size_t n : {3000, 10000, 30000, 100000, 300000, 1000000}) {
    if (n > largest) break;
    last = n;
    const Points cloud = densified(held, n, rng);
    std::vector<PointCloud> parts;
    for (const auto& view : views) parts.push_back({densified(view, n / views.size(), rng), {}, {}, "hand"});
    const double times[3] = {
        median_ms([&] { find_tooltip(cloud, estimate_tool_frame(cloud)); }),
        median_ms([&] { merge_views(parts); }),
        median_ms([&] { align_pose(model, cloud); }),
    };
    std::printf("  %9zu  %11.1f ms  %13.1f ms  %11.1f ms  %8.0f\n", n, times[0], times[1], times[2], peak_rss_mb());
    if (n < 10000) continue;
    log_n.push_back(std::log(static_cast<double>(n)));
    for (int j = 0; j < 3; ++j) log_time[j].push_back(std::log(times[j]));
  }
  const auto slope = [&](const std::vector<double>& y) {
    const double mx = std::accumulate(log_n.begin(), log_n.end(), 0.0) / static_cast<double>(log_n.size());
    const double my = std::accumulate(y.begin(), y.end(), 0.0) / static_cast<double>(y.size());
    double sxy = 0.0, sxx = 0.0;
    for (std::size_t i = 0; i < y.size(); ++i) {
      sxy += (log_n[i] - mx) * (y[i] - my);
      sxx += (log_n[i] - mx) * (log_n[i] - mx);
    }
    return sxy / sxx;
  };
  if (log_n.size() < 2) {
    std::printf("  exponent: needs two sizes from 10k points up\n");
    return;
  }
  std::printf("  %9s  %14.2f  %16.2f  %14.2f   (time ~ points^exponent, 10k-%s)\n", "exponent", slope(log_time[0]),
              slope(log_time[1]), slope(log_time[2]),
              last >= 1000000 ? "1M" : (std::to_string(last / 1000) + "k").c_str());
}

}  // namespace

// bench_peers [MIN_TIME_S [LARGEST]]: each median over at least MIN_TIME_S (0.5) seconds of runs; the
// scaling up to LARGEST points (1000000).
int main(int argc, char** argv) {
  if (argc > 1) min_time_ms = 1000.0 * std::atof(argv[1]);
  const std::size_t largest = argc > 2 ? static_cast<std::size_t>(std::atof(argv[2])) : 1000000;
#ifdef _OPENMP
  omp_set_num_threads(1);
#endif
  std::printf("toolinc against its peers, one core; median times; x = ratio to the fastest peer\n");
  // A held tool's model, about 10k points, and one partial view of it, about 5k points (as bench_align_pose).
  const PartialViewCase held = make_partial_view_case(ToolFamily::hoe, 7);
  ToolShape shape = held.shape;
  Points model;
  for (int i = 0; i < 4; ++i) {
    model = generate_tool(shape, 1).points;
    shape.spacing *= std::sqrt(static_cast<double>(model.size()) / 10000.0);
  }
  PartialViewConfig view_config;
  Points view;
  for (int i = 0; i < 4; ++i) {
    view = make_partial_view_case(ToolFamily::hoe, 7, any_grasp_range(), view_config).view;
    view_config.spacing *= std::sqrt(static_cast<double>(view.size()) / 5000.0);
  }
  // A session of the robot's stereo: one cropped view (a real-size view) and the merged model.
  const std::vector<PointCloud> views = session_views(ToolFamily::hoe, 7).views;
  const Points merged = merge_views(views).model.points;

  neighbour_search("held tool", model);
  neighbour_search("merged session model", merged);
  filters("cropped view", views.front().points);
  filters("held tool", model);
  Eigen::Matrix4d error = Eigen::Matrix4d::Identity();
  error.topLeftCorner<3, 3>() = Eigen::AngleAxisd(3.0 * M_PI / 180.0, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  error.topRightCorner<3, 1>() = Vec3(0.003, -0.003, 0.0025);
  const Eigen::Matrix4d truth = held.grasp.inverse();  // model_from_view
  icp(model, view, truth, error * truth);
  whole_align_pose(min_time_ms < 100.0 ? 1 : 5);
  whole_merge_views(min_time_ms < 100.0 ? 1 : 2);
  scaling(family_session(ToolFamily::hoe, 7), largest);
  return 0;
}
