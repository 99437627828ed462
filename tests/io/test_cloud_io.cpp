// Point-cloud reading and writing: PLY and PCD variants, atomic writes. Malformed files: test_malformed_files.cpp.
#include <gtest/gtest.h>
#include <lzf.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/cloud_files.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/atomic_file.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/read_file.hpp"

namespace toolinc {
namespace {

namespace fs = std::filesystem;
using testing::bytes_of;
using testing::compressed_pcd;
using testing::expect_read_error;
using testing::u8;

// A fresh folder per test, removed afterwards.
class CloudIo : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() / ("toolinc_cloud_io_" + std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  std::string write(const std::string& name, const std::string& bytes) const {
    const std::string file = path(name);
    std::ofstream(file, std::ios::binary) << bytes;
    return file;
  }

  fs::path dir_;
};

// The test's own LZF compressor: greedy longest match within the 8 KiB window, literal runs otherwise.
// liblzf's own compressor (Debian's liblzf, the library PCL's format comes from), so the reader is tested
// on streams it did not produce itself.
std::string lzf_compress(const std::string& in) {
  std::string out(in.size() + in.size() / 16 + 64, '\0');
  const unsigned size =
      ::lzf_compress(in.data(), static_cast<unsigned>(in.size()), out.data(), static_cast<unsigned>(out.size()));
  if (size == 0) throw std::runtime_error("lzf_compress failed");
  out.resize(size);
  return out;
}

float packed_rgb_float(std::uint8_t r, std::uint8_t g, std::uint8_t b) {
  const std::uint32_t packed = (std::uint32_t{r} << 16) | (std::uint32_t{g} << 8) | b;
  float value;
  std::memcpy(&value, &packed, 4);
  return value;
}

void expect_point(const Vec3& actual, double x, double y, double z) {
  EXPECT_NEAR(actual.x(), x, 1e-6);
  EXPECT_NEAR(actual.y(), y, 1e-6);
  EXPECT_NEAR(actual.z(), z, 1e-6);
}

PointCloud sample_cloud() {
  PointCloud cloud;
  cloud.frame = "hand";
  cloud.points = {{0.1, -0.25, 3.5}, {1e-7, 987.654321, -0.0}, {-1.5, 2.25, 0.333333}};
  cloud.colors = {{{255, 0, 10}}, {{1, 2, 3}}, {{128, 64, 32}}};
  cloud.normals = {{0, 0, 1}, {0.6, 0.8, 0}, {-1, 0, 0}};
  return cloud;
}

void expect_same_as_float(const PointCloud& read, const PointCloud& written) {
  ASSERT_EQ(read.size(), written.size());
  EXPECT_EQ(read.frame, written.frame);
  EXPECT_EQ(read.colors, written.colors);
  ASSERT_EQ(read.normals.size(), written.normals.size());
  for (std::size_t i = 0; i < read.size(); ++i) {
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(read.points[i][axis], static_cast<double>(static_cast<float>(written.points[i][axis])));
      EXPECT_EQ(read.normals[i][axis], static_cast<double>(static_cast<float>(written.normals[i][axis])));
    }
  }
}

TEST_F(CloudIo, AsciiPlyWithDiffuseColoursAndFaces) {
  const std::string file =
      write("a.ply",
            "ply\r\nformat ascii 1.0\r\ncomment made by hand\r\ncomment frame root\r\n"
            "element vertex 3\r\nproperty float x\r\nproperty float y\r\nproperty float z\r\n"
            "property uchar diffuse_red\r\nproperty uchar diffuse_green\r\nproperty uchar diffuse_blue\r\n"
            "element face 2\r\nproperty list uchar int vertex_indices\r\nend_header\r\n"
            "0 0 0 255 0 0\r\n1 0 0 0 255 0\r\n0 1.5 -2e-1 0 0 255\r\n3 0 1 2\r\n4 0 1 2 0\r\n");
  CloudReadStats stats;
  const PointCloud cloud = read_cloud(file, &stats);
  ASSERT_EQ(cloud.size(), 3u);
  EXPECT_EQ(stats.points_in_file, 3u);
  EXPECT_EQ(cloud.frame, "root");
  expect_point(cloud.points[2], 0, 1.5, -0.2);
  ASSERT_TRUE(cloud.has_colors());
  EXPECT_EQ(cloud.colors[1], (Rgb{0, 255, 0}));
  EXPECT_FALSE(cloud.has_normals());
}

// A binary PLY with a "camera" element first, vertices with reordered mixed-type properties (double
// x/y/z, float colours in 0..1, a list inside the vertex) and a face list element after them.
std::string reordered_binary_ply(bool big_endian) {
  const auto le = [big_endian](auto value) { return bytes_of(value, big_endian); };
  std::string ply = std::string("ply\nformat ") + (big_endian ? "binary_big_endian" : "binary_little_endian") +
                    " 1.0\ncomment frame canonical\n"
                    "element camera 1\nproperty float view_px\nproperty int16 tag\n"
                    "element vertex 2\nproperty float nx\nproperty float32 red\nproperty double y\n"
                    "property float64 x\nproperty list uint8 uint16 extra\nproperty double z\nproperty float green\n"
                    "property float blue\nproperty float ny\nproperty float nz\nproperty uint8 flags\n"
                    "element face 1\nproperty list uchar int vertex_indices\nend_header\n";
  ply += le(1.5f) + le(std::int16_t{-7});
  ply += le(0.0f) + le(1.0f) + le(2.0) + le(1.0) + u8(2) + le(std::uint16_t{9}) + le(std::uint16_t{10}) + le(3.0) +
         le(0.5f) + le(0.0f) + le(0.0f) + le(1.0f) + u8(0xff);
  ply +=
      le(1.0f) + le(0.0f) + le(-5.0) + le(-4.0) + u8(0) + le(-6.0) + le(0.0f) + le(1.0f) + le(0.0f) + le(0.0f) + u8(0);
  ply += u8(3) + le(std::int32_t{0}) + le(std::int32_t{1}) + le(std::int32_t{0});
  return ply;
}

void expect_reordered_cloud(const PointCloud& cloud) {
  ASSERT_EQ(cloud.size(), 2u);
  EXPECT_EQ(cloud.frame, "canonical");
  expect_point(cloud.points[0], 1, 2, 3);
  expect_point(cloud.points[1], -4, -5, -6);
  ASSERT_TRUE(cloud.has_colors());
  EXPECT_EQ(cloud.colors[0], (Rgb{255, 128, 0}));
  EXPECT_EQ(cloud.colors[1], (Rgb{0, 0, 255}));
  ASSERT_TRUE(cloud.has_normals());
  expect_point(cloud.normals[0], 0, 0, 1);
  expect_point(cloud.normals[1], 1, 0, 0);
}

TEST_F(CloudIo, BinaryLittleEndianPlyWithReorderedPropertiesAndExtraElements) {
  expect_reordered_cloud(read_cloud(write("le.ply", reordered_binary_ply(false))));
}

TEST_F(CloudIo, BinaryBigEndianPlyWithReorderedPropertiesAndExtraElements) {
  expect_reordered_cloud(read_cloud(write("be.ply", reordered_binary_ply(true))));
}

TEST_F(CloudIo, BinaryRoundTripKeepsColoursNormalsAndFrame) {
  const PointCloud cloud = sample_cloud();
  write_ply(path("rt.ply"), cloud, {false, "toolinc-x --in a.ply\n--out rt.ply"});
  const std::string bytes = read_file(path("rt.ply"));
  EXPECT_NE(bytes.find("format binary_little_endian 1.0\n"), std::string::npos);
  EXPECT_NE(bytes.find("comment command toolinc-x --in a.ply --out rt.ply\n"), std::string::npos);
  expect_same_as_float(read_cloud(path("rt.ply")), cloud);
}

TEST_F(CloudIo, AsciiRoundTripKeepsColoursNormalsAndFrame) {
  const PointCloud cloud = sample_cloud();
  write_ply(path("rt.ply"), cloud, {true, ""});
  const std::string bytes = read_file(path("rt.ply"));
  EXPECT_EQ(
      bytes.rfind("ply\nformat ascii 1.0\ncomment generated by toolinc\ncomment frame hand\nelement vertex 3\n", 0),
      0u);
  EXPECT_EQ(bytes.find("comment command"), std::string::npos);
  expect_same_as_float(read_cloud(path("rt.ply")), cloud);
}

TEST_F(CloudIo, WritingIsDeterministic) {
  for (const bool ascii : {false, true}) {
    write_ply(path("one.ply"), sample_cloud(), {ascii, "cmd"});
    write_ply(path("two.ply"), sample_cloud(), {ascii, "cmd"});
    EXPECT_EQ(read_file(path("one.ply")), read_file(path("two.ply")));
  }
}

TEST_F(CloudIo, PointsOnlyRoundTripHasNoColoursOrNormals) {
  PointCloud cloud;
  cloud.points = {{1, 2, 3}};
  write_ply(path("p.ply"), cloud);
  const PointCloud read = read_cloud(path("p.ply"));
  ASSERT_EQ(read.size(), 1u);
  EXPECT_FALSE(read.has_colors());
  EXPECT_FALSE(read.has_normals());
  EXPECT_TRUE(read.frame.empty());
}

TEST_F(CloudIo, PcdAsciiWithPackedFloatRgb) {
  char line[128];
  std::snprintf(line, sizeof line, "1 2 3 %.9g\n-1 0.5 2 %.9g\n", packed_rgb_float(10, 20, 30),
                packed_rgb_float(255, 0, 128));
  const std::string file = write("a.pcd",
                                 "# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS x y z rgb\n"
                                 "SIZE 4 4 4 4\nTYPE F F F F\nCOUNT 1 1 1 1\nWIDTH 2\nHEIGHT 1\n"
                                 "VIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\n" +
                                     std::string(line));
  const PointCloud cloud = read_cloud(file);
  ASSERT_EQ(cloud.size(), 2u);
  expect_point(cloud.points[1], -1, 0.5, 2);
  ASSERT_TRUE(cloud.has_colors());
  EXPECT_EQ(cloud.colors[0], (Rgb{10, 20, 30}));
  EXPECT_EQ(cloud.colors[1], (Rgb{255, 0, 128}));
}

TEST_F(CloudIo, PcdOldHeaderWithoutVersionOrPoints) {
  const std::string file = write("old.pcd",
                                 "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 2\nDATA ascii\n"
                                 "0 0 0\n1 0 0\n0 1 0\n0 0 1\n");
  const PointCloud cloud = read_cloud(file);
  ASSERT_EQ(cloud.size(), 4u);
  expect_point(cloud.points[3], 0, 0, 1);
}

// One point's fields: x y z (float), fpfh (33 floats), normals (double), rgba (uint32).
std::string pcd_binary_point(float x, float y, float z, double nz, std::uint32_t rgba) {
  std::string point = bytes_of(x) + bytes_of(y) + bytes_of(z);
  for (int k = 0; k < 33; ++k) point += bytes_of(static_cast<float>(k));
  return point + bytes_of(0.0) + bytes_of(0.0) + bytes_of(nz) + bytes_of(rgba);
}

TEST_F(CloudIo, PcdBinaryWithCount33FieldAndOrganisedCloud) {
  const std::string header =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z fpfh normal_x normal_y normal_z rgba\nSIZE 4 4 4 4 8 8 8 4\n"
      "TYPE F F F F F F F U\nCOUNT 1 1 1 33 1 1 1 1\nWIDTH 2\nHEIGHT 2\nVIEWPOINT 0 0 0 1 0 0 0\n"
      "POINTS 4\nDATA binary\n";
  std::string data;
  for (int i = 0; i < 4; ++i) data += pcd_binary_point(i, 2.0f * i, -1.0f, 1.0, 0xff000000u | (i * 0x010203u));
  const PointCloud cloud = read_cloud(write("b.pcd", header + data));
  ASSERT_EQ(cloud.size(), 4u);
  expect_point(cloud.points[3], 3, 6, -1);
  ASSERT_TRUE(cloud.has_normals());
  expect_point(cloud.normals[2], 0, 0, 1);
  ASSERT_TRUE(cloud.has_colors());
  EXPECT_EQ(cloud.colors[3], (Rgb{3, 6, 9}));
}

TEST_F(CloudIo, PcdBinaryCompressedFieldByField) {
  // Structure of arrays as PCL writes it: all x, all y, all z, all rgb; the padding field "_" is absent.
  const int n = 50;
  std::string xs, ys, zs, rgbs;
  for (int i = 0; i < n; ++i) {
    xs += bytes_of(0.5f * i);
    ys += bytes_of(1.0f);
    zs += bytes_of(-0.25f * (i % 5));
    rgbs += bytes_of(packed_rgb_float(static_cast<std::uint8_t>(i), 7, 200));
  }
  const std::string raw = xs + ys + zs + rgbs;
  const std::string compressed = lzf_compress(raw);
  ASSERT_LT(compressed.size(), raw.size());  // back-references were used
  const std::string file = write("c.pcd", compressed_pcd("FIELDS x y z _ rgb\nSIZE 4 4 4 1 4\nTYPE F F F U F\n"
                                                         "COUNT 1 1 1 4 1\n",
                                                         n, raw, compressed));
  const PointCloud cloud = read_cloud(file);
  ASSERT_EQ(cloud.size(), static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    expect_point(cloud.points[i], 0.5 * i, 1, -0.25 * (i % 5));
    EXPECT_EQ(cloud.colors[i], (Rgb{static_cast<std::uint8_t>(i), 7, 200}));
  }
}

TEST_F(CloudIo, PcdBinaryCompressedHandMadeBackReference) {
  // Four points at x = y = z = 1: each 16-byte column is a 4-byte literal and a 12-byte back-reference
  // (length 12 -> control 7 << 5 plus extra byte 3; distance 4 -> offset byte 3).
  const std::string one = bytes_of(1.0f);
  const std::string column = u8(3) + one + u8(0xe0) + u8(3) + u8(3);
  const std::string raw = one + one + one + one + one + one + one + one + one + one + one + one;
  const std::string file =
      write("h.pcd", compressed_pcd("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n", 4, raw, column + column + column));
  const PointCloud cloud = read_cloud(file);
  ASSERT_EQ(cloud.size(), 4u);
  for (const Vec3& p : cloud.points) expect_point(p, 1, 1, 1);
}

TEST_F(CloudIo, NonFinitePointsAreDroppedAndCounted) {
  const std::string file = write("nan.ply",
                                 "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                                 "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
                                 "end_header\n1 1 1 1 1 1\nnan 0 0 2 2 2\n0 inf 0 3 3 3\n4 4 4 4 4 4\n");
  CloudReadStats stats;
  const PointCloud cloud = read_cloud(file, &stats);
  EXPECT_EQ(stats.points_in_file, 4u);
  EXPECT_EQ(stats.non_finite_dropped, 2u);
  ASSERT_EQ(cloud.size(), 2u);
  ASSERT_EQ(cloud.colors.size(), 2u);
  expect_point(cloud.points[1], 4, 4, 4);
  EXPECT_EQ(cloud.colors[1], (Rgb{4, 4, 4}));

  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::string pcd = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nDATA binary\n" + bytes_of(nan) +
                          bytes_of(nan) + bytes_of(nan) + bytes_of(1.0f) + bytes_of(2.0f) + bytes_of(3.0f);
  EXPECT_EQ(read_cloud(write("nan.pcd", pcd), &stats).size(), 1u);
  EXPECT_EQ(stats.non_finite_dropped, 1u);
}

TEST_F(CloudIo, PcdBinaryCompressedLargeCloudFromLiblzf) {
  // 20000 points of smooth data: long back-references, literal runs and the 8 KB window all exercised.
  const int n = 20000;
  std::string xs, ys, zs;
  for (int i = 0; i < n; ++i) {
    xs += bytes_of(static_cast<float>(std::sin(i * 0.01)));
    ys += bytes_of(static_cast<float>(i % 97) * 0.001f);
    zs += bytes_of(0.5f);
  }
  const std::string raw = xs + ys + zs;
  const PointCloud cloud =
      read_cloud(write("big.pcd", compressed_pcd("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n", n, raw, lzf_compress(raw))));
  ASSERT_EQ(cloud.size(), static_cast<std::size_t>(n));
  for (int i = 0; i < n; i += 997)
    expect_point(cloud.points[i], static_cast<float>(std::sin(i * 0.01)), static_cast<float>(i % 97) * 0.001f, 0.5);
  // Cut one byte off the stream: the decoder must notice, not read past the end.
  std::string cut = lzf_compress(raw);
  cut.pop_back();
  expect_read_error(write("cut.pcd", compressed_pcd("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n", n, raw, cut)), "corrupt");
}

TEST_F(CloudIo, PcdViewpointIsCarriedAsTheCloudsViewpoint) {
  const std::string body = "WIDTH 1\nHEIGHT 1\nPOINTS 1\nDATA ascii\n1 2 3\n";
  const std::string fields = "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n";
  const PointCloud seen = read_cloud(write("v.pcd", fields + "VIEWPOINT 0.1 -0.2 0.35 0.5 0.5 0.5 0.5\n" + body));
  ASSERT_EQ(seen.viewpoints.size(), 1u);
  expect_point(seen.viewpoints[0], 0.1, -0.2, 0.35);
  // PCL's default (origin, identity) means "unknown": no viewpoint, as with a PLY without the comment.
  EXPECT_TRUE(read_cloud(write("d.pcd", fields + "VIEWPOINT 0 0 0 1 0 0 0\n" + body)).viewpoints.empty());
  expect_read_error(write("bad.pcd", fields + "VIEWPOINT 0 0 nan 1 0 0 0\n" + body), "VIEWPOINT");
  expect_read_error(write("short.pcd", fields + "VIEWPOINT 1 2 3\n" + body), "VIEWPOINT");
}

TEST_F(CloudIo, AtomicWriteLeavesNothingWhenTheWriterThrows) {
  const std::string target = path("out.txt");
  const auto failing = [](std::ostream& out) {
    out << "partial";
    throw std::runtime_error("writer failed");
  };
  EXPECT_THROW(write_file_atomic(target, failing), std::runtime_error);
  EXPECT_TRUE(fs::is_empty(dir_));  // neither the target nor a temporary file

  write_file_atomic(target, [](std::ostream& out) { out << "old contents"; });
  EXPECT_THROW(write_file_atomic(target, failing), std::runtime_error);
  EXPECT_EQ(read_file(target), "old contents");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(CloudIo, AtomicWriteIntoMissingFolderIsAnInputError) {
  const std::string target = path("no/such/dir/out.ply");
  try {
    write_ply(target, sample_cloud());
    ADD_FAILURE() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(target + ": cannot write: No such file or directory"), std::string::npos)
        << error.what();
  }
}

TEST_F(CloudIo, LargeBinaryPlyRoundTrip) {
  PointCloud cloud;
  for (int i = 0; i < 100000; ++i) {
    cloud.points.emplace_back(i * 1e-3, -i * 2e-3, std::sin(i));
    cloud.colors.push_back({static_cast<std::uint8_t>(i), static_cast<std::uint8_t>(i >> 8), 7});
  }
  write_ply(path("big.ply"), cloud);
  const PointCloud read = read_cloud(path("big.ply"));
  ASSERT_EQ(read.size(), cloud.size());
  EXPECT_EQ(read.colors, cloud.colors);
  EXPECT_FLOAT_EQ(static_cast<float>(read.points[99999].z()), static_cast<float>(std::sin(99999)));
}

}  // namespace
}  // namespace toolinc
