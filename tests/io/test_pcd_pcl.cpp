// PCD files written by PCL itself (pcl::io, every encoding, a non-trivial VIEWPOINT) read identically by
// toolinc's reader: points, colours, normals and the sensor origin.
#include <gtest/gtest.h>
#include <pcl/io/pcd_io.h>
#include <pcl/point_types.h>
#include <unistd.h>

#include <filesystem>
#include <random>

#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/pcd_write.hpp"

namespace toolinc {
namespace {

namespace fs = std::filesystem;

pcl::PointCloud<pcl::PointXYZRGBNormal> pcl_cloud(int width, int height) {
  pcl::PointCloud<pcl::PointXYZRGBNormal> cloud(width, height);
  std::mt19937 random(7);
  std::uniform_real_distribution<float> coordinate(-0.3f, 0.3f);
  std::uniform_int_distribution<int> byte(0, 255);
  for (auto& p : cloud.points) {
    p.x = coordinate(random), p.y = coordinate(random), p.z = coordinate(random);
    p.r = static_cast<std::uint8_t>(byte(random)), p.g = static_cast<std::uint8_t>(byte(random));
    p.b = static_cast<std::uint8_t>(byte(random));
    const Eigen::Vector3f n = Eigen::Vector3f(coordinate(random), coordinate(random), 0.5f).normalized();
    p.normal_x = n.x(), p.normal_y = n.y(), p.normal_z = n.z();
    p.curvature = coordinate(random);
  }
  cloud.sensor_origin_ = Eigen::Vector4f(0.125f, -0.25f, 0.375f, 0.0f);
  cloud.sensor_orientation_ = Eigen::Quaternionf(0.5f, 0.5f, 0.5f, 0.5f);
  return cloud;
}

class PclWritten : public ::testing::TestWithParam<int> {};

TEST_P(PclWritten, ReadsIdentically) {
  const fs::path dir = fs::temp_directory_path() / ("toolinc_pcd_pcl_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string file = (dir / ("cloud" + std::to_string(GetParam()) + ".pcd")).string();
  const int width = 37, height = 11;
  const auto written = pcl_cloud(width, height);
  pcl::PCDWriter writer;
  switch (GetParam()) {
    case 0:
      ASSERT_EQ(writer.writeASCII(file, written, 9), 0);
      break;
    case 1:
      ASSERT_EQ(writer.writeBinary(file, written), 0);
      break;
    case 2:
      ASSERT_EQ(writer.writeBinaryCompressed(file, written), 0);
      break;
  }
  const PointCloud read = read_cloud(file);
  ASSERT_EQ(read.size(), written.size());
  ASSERT_TRUE(read.has_colors());
  ASSERT_TRUE(read.has_normals());
  for (std::size_t i = 0; i < read.size(); ++i) {
    const auto& p = written.points[i];
    // Floats written with 9 significant digits (ascii) or as bits read back as the same float.
    EXPECT_EQ(read.points[i], Vec3(p.x, p.y, p.z)) << i;
    EXPECT_EQ(read.normals[i], Vec3(p.normal_x, p.normal_y, p.normal_z)) << i;
    EXPECT_EQ(read.colors[i], (Rgb{p.r, p.g, p.b})) << i;
  }
  ASSERT_EQ(read.viewpoints.size(), 1u);
  EXPECT_EQ(read.viewpoints[0], Vec3(0.125, -0.25, 0.375));
  // The organised reader sees the same points, in PCL's row-major order.
  const Points organised = read_organised_pcd(file, width, height);
  ASSERT_EQ(organised.size(), written.size());
  for (std::size_t i = 0; i < organised.size(); ++i) EXPECT_EQ(organised[i], read.points[i]);
  fs::remove_all(dir);
}

std::string encoding_name(const ::testing::TestParamInfo<int>& info) {
  static const char* const kNames[] = {"ascii", "binary", "binary_compressed"};
  return kNames[info.param];
}

INSTANTIATE_TEST_SUITE_P(Encodings, PclWritten, ::testing::Values(0, 1, 2), encoding_name);

// And the other way: PCL reads what write_pcd writes (NaN pixels kept).
TEST(PclReads, OurOrganisedPcd) {
  const std::string file =
      (fs::temp_directory_path() / ("toolinc_pcd_ours_" + std::to_string(::getpid()) + ".pcd")).string();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Points points{{0.5, -1, 2}, {nan, nan, nan}, {3, 4.25, -5}, {0, 0, 1e-3}, {1, 1, 1}, {-2, 0, 7}};
  write_pcd(file, points, 3, 2);
  pcl::PointCloud<pcl::PointXYZ> cloud;
  ASSERT_EQ(pcl::io::loadPCDFile(file, cloud), 0);
  ASSERT_EQ(cloud.width, 3u);
  ASSERT_EQ(cloud.height, 2u);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!points[i].allFinite()) {
      EXPECT_TRUE(std::isnan(cloud.points[i].x));
      continue;
    }
    EXPECT_EQ(Vec3(cloud.points[i].x, cloud.points[i].y, cloud.points[i].z), points[i].cast<float>().cast<double>());
  }
  fs::remove(file);
}

}  // namespace
}  // namespace toolinc
