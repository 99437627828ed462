// Every reader's malformed and lying files, in one place: clouds (PLY, PCD, binary_compressed PCD, organised
// PCD), JSON, feature rows. Each must be bad input (InputError, exit 2 through the tools) whose one-line
// message names the file and the problem, found before anything is allocated for what a header promises.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

#include "support/cloud_files.hpp"
#include "support/files.hpp"
#include "support/input_error_of.hpp"
#include "support/paths.hpp"
#include "support/run_tool.hpp"
#include "toolinc/appearance/feature_db.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/io/limits.hpp"
#include "toolinc/io/pcd_write.hpp"
#include "toolinc/io/read_file.hpp"

namespace toolinc {
namespace {

namespace fs = std::filesystem;
using testing::bytes_of;
using testing::compressed_pcd;
using testing::expect_failure_left_nothing;
using testing::expect_read_error;
using testing::input_error_of;
using testing::run_tool;
using testing::scratch_dir;
using testing::ToolRun;
using testing::u8;
using testing::write_text;

// A fresh folder per test.
class MalformedCloud : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = scratch_dir(std::string("malformed_") + test_info()->name()); }
  static const ::testing::TestInfo* test_info() { return ::testing::UnitTest::GetInstance()->current_test_info(); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& bytes) const {
    write_text(dir_ / name, bytes);
    return path(name);
  }
  fs::path dir_;
};

// f must throw an InputError naming file and saying what.
template <class F>
void expect_error_naming(F&& f, const std::string& file, const std::string& what) {
  const std::string message = input_error_of(std::forward<F>(f));
  EXPECT_NE(message.find(file), std::string::npos) << message;
  EXPECT_NE(message.find(what), std::string::npos) << message;
}

std::string nested(std::size_t depth) { return std::string(depth, '[') + std::string(depth, ']'); }

// --- clouds ------------------------------------------------------------------------------------------

TEST_F(MalformedCloud, PcdBinaryCompressedCorruptStreamIsAnInputError) {
  const std::string one = bytes_of(1.0f);
  // The back-reference reaches 8 bytes back when only 4 have been written.
  const std::string bad = u8(3) + one + u8(0xe0) + u8(3) + u8(7);
  const std::string raw(48, '\0');
  expect_read_error(write("bad.pcd", compressed_pcd("FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n", 4, raw, bad + bad + bad)),
                    "corrupt");
}

TEST_F(MalformedCloud, MissingFileIsAnInputError) { expect_read_error(path("nope.ply"), "No such file"); }

TEST_F(MalformedCloud, EmptyFileIsAnInputError) { expect_read_error(write("empty.ply", ""), "empty"); }

TEST_F(MalformedCloud, GarbageFileIsAnInputError) {
  expect_read_error(write("junk.ply", std::string("\x89PNG\r\n\x1a\n\0\0garbage", 18)), "not a PLY or PCD");
}

TEST_F(MalformedCloud, TruncatedBinaryPlyIsAnInputError) {
  PointCloud cloud;
  cloud.points.assign(10, Vec3(1, 2, 3));
  write_ply(path("full.ply"), cloud);
  const std::string bytes = read_file(path("full.ply"));
  const std::string file = write("cut.ply", bytes.substr(0, bytes.size() - 20));
  expect_read_error(file, "truncated");
  expect_read_error(file, "expected 10 vertices, file ends at vertex 8");
}

TEST_F(MalformedCloud, BadPlyHeadersAreInputErrors) {
  expect_read_error(write("noxyz.ply",
                          "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                          "end_header\n1 2\n"),
                    "no x/y/z");
  expect_read_error(write("noend.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\n"), "end_header");
  expect_read_error(write("fmt.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n"), "format");
  expect_read_error(write("elem.ply", "ply\nformat ascii 1.0\nelement vertex many\nend_header\n"), "element");
  expect_read_error(write("type.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\nend_header\n"),
                    "quad");
  for (const std::string keyword : {"recorded-views", "unmerged-views"})
    for (const char* count : {"-1", "2.5", "two", "1e9"})
      expect_read_error(write("count.ply", "ply\nformat ascii 1.0\ncomment " + keyword + " " + count +
                                               "\nelement vertex 1\nproperty float x\nproperty float y\n"
                                               "property float z\nend_header\n1 2 3\n"),
                        "bad " + keyword + " comment");
}

TEST_F(MalformedCloud, BadAsciiNumberNamesTheLine) {
  const std::string file = write("num.ply",
                                 "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                                 "property float z\nend_header\n1 2 3\n4 five 6\n");
  expect_read_error(file, "line 9");
  expect_read_error(file, "five");
}

TEST_F(MalformedCloud, ViewsThatAreNoBitMaskNameTheVertex) {
  for (const char* value : {"-1", "1.5", "4294967296"}) {
    const std::string file = write("views.ply",
                                   "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
                                   "property float z\nproperty double views\nend_header\n1 2 3 1\n4 5 6 " +
                                       std::string(value) + "\n");
    expect_read_error(file, "vertex 1: views");
  }
}

TEST_F(MalformedCloud, BadPcdHeadersAreInputErrors) {
  expect_read_error(write("kind.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 1\nDATA foo\n"), "DATA");
  expect_read_error(write("size.pcd", "FIELDS x y z\nSIZE 4 4\nTYPE F F F\nWIDTH 1\nDATA ascii\n1 2 3\n"), "SIZE");
  expect_read_error(write("width.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH lots\nDATA ascii\n"), "WIDTH");
  expect_read_error(write("noxyz.pcd", "FIELDS x y\nSIZE 4 4\nTYPE F F\nWIDTH 1\nDATA ascii\n1 2\n"), "no x/y/z");
  expect_read_error(
      write("short.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 3\nDATA binary\n" + std::string(20, '\0')),
      "truncated");
}

// Regression: SIZE x COUNT wrapping to 0 or a few bytes gave a division by zero, reads past
// the buffer and, for one binary file, a cloud made up from nothing.
TEST_F(MalformedCloud, PcdRecordWidthOverflowIsAnInputError) {
  const std::string tail = "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary\n" + std::string(64, '\x01');
  expect_read_error(write("count.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 4611686018427387904 1 1\n" + tail),
                    "SIZE x COUNT");
  expect_read_error(
      write("pad.pcd", "FIELDS x y z _\nSIZE 4 4 4 1\nTYPE F F F U\nCOUNT 1 1 1 18446744073709551608\n" + tail),
      "SIZE x COUNT");
  const std::string compressed_tail =
      "WIDTH 2\nHEIGHT 1\nPOINTS 2\nDATA binary_compressed\n" + bytes_of(4u) + bytes_of(0u) + std::string(4, '\x01');
  expect_read_error(
      write("count_c.pcd", "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 4611686018427387904 1\n" + compressed_tail),
      "SIZE x COUNT");
  expect_read_error(write("count_a.pcd",
                          "FIELDS x y z\nSIZE 8 4 4\nTYPE F F F\nCOUNT 2305843009213693952 1 1\n"
                          "WIDTH 1\nDATA ascii\n1 2 3\n"),
                    "SIZE x COUNT");
  // Absurd declared sizes are bad input before anything is allocated.
  expect_read_error(write("huge.pcd",
                          "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 18446744073709551615\nHEIGHT 1\n"
                          "DATA binary\n" +
                              std::string(24, '\0')),
                    "more than the 10000000 a cloud may hold");
}

TEST(CloudLimits, CompressedPcdPromisingTooManyPointsIsRefusedBeforeAllocating) {
  const fs::path dir = scratch_dir("pcd_bomb");
  const std::size_t points = kMaxCloudPoints + 1;
  const std::uint32_t uncompressed = static_cast<std::uint32_t>(points * 12);
  const std::uint32_t compressed = uncompressed / 80;  // passes the LZF ratio check
  std::ofstream(dir / "bomb.pcd", std::ios::binary)
      << "VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH " << points << "\nHEIGHT 1\nPOINTS "
      << points << "\nDATA binary_compressed\n"
      << bytes_of(compressed) << bytes_of(uncompressed) << std::string(compressed, '\0');
  const std::string message = input_error_of([&] { read_cloud((dir / "bomb.pcd").string()); });
  EXPECT_NE(message.find("bomb.pcd: PCD header: 10000001 points, more than the 10000000 a cloud may hold"),
            std::string::npos)
      << message;
}

TEST(CloudLimits, PlyVertexCountBeyondTheLimitIsRefused) {
  const fs::path dir = scratch_dir("ply_count");
  std::ofstream(dir / "lie.ply", std::ios::binary)
      << "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nproperty uchar x\nproperty uchar y\n"
         "property uchar z\nend_header\n"
      << std::string(3000, '\1');
  const std::string message = input_error_of([&] { read_cloud((dir / "lie.ply").string()); });
  EXPECT_NE(message.find("lie.ply: PLY header: 4000000000 vertices, more than the 10000000"), std::string::npos)
      << message;
}

// Regression: the organised reader was a second parser whose length check underflowed on a
// header ending in "DATA binary" without a newline (and read ~900 KB past the buffer), and whose record
// width wrapped on SIZE x COUNT. It is now the one PCD reader, so both are bad input.
TEST(MalformedOrganisedPcd, TruncatedHeaderOverflowingCountsAndLyingPointsAreInputErrors) {
  const fs::path dir = scratch_dir("pcd_bad");
  const std::string no_newline = (dir / "no_newline.pcd").string();
  std::ofstream(no_newline) << "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 320\nHEIGHT 240\nDATA binary";
  expect_error_naming([&] { read_organised_pcd(no_newline, 320, 240); }, no_newline, "truncated");
  const std::string overflow = (dir / "overflow.pcd").string();
  std::ofstream(overflow) << "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 4611686018427387904\nWIDTH 2\nHEIGHT 1\n"
                             "DATA binary\n"
                          << std::string(24, '\x01');
  expect_error_naming([&] { read_organised_pcd(overflow, 2, 1); }, overflow, "SIZE x COUNT");
  // POINTS disagreeing with WIDTH x HEIGHT: which pixel is which point is unknown.
  const std::string lying = (dir / "lying.pcd").string();
  std::ofstream(lying)
      << "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nHEIGHT 1\nPOINTS 3\nDATA ascii\n1 2 3\n4 5 6\n";
  expect_error_naming([&] { read_organised_pcd(lying, 2, 1); }, lying, "3 points");
}

// --- JSON ---------------------------------------------------------------------------------------------

TEST(MalformedJson, DepthAndSizeAreCheckedBeforeParsing) {
  EXPECT_NO_THROW(parse_json("{\"a\": " + nested(kMaxJsonDepth - 1) + "}", "f.json"));
  const std::string deep =
      input_error_of([] { parse_json("{\"deep\": " + nested(50000) + ", \"type\": 1}", "f.json"); });
  EXPECT_NE(deep.find("f.json: JSON nested more than 64 levels"), std::string::npos) << deep;
  // Brackets inside strings (escaped quotes included) are text, not nesting.
  EXPECT_NO_THROW(parse_json("{\"s\": \"\\\"" + std::string(1000, '[') + "\"}", "f.json"));
  const std::string big = input_error_of([] { check_json_limits(std::string(kMaxJsonBytes + 1, ' '), "big.json"); });
  EXPECT_NE(big.find("big.json: JSON of"), std::string::npos) << big;
}

TEST(MalformedJson, NumberOutOfRangeIsBadInputNamingTheFile) {
  const std::string message = input_error_of([] { parse_json("{\"x\": 1e400}", "n.json"); });
  EXPECT_NE(message.find("n.json: not valid JSON"), std::string::npos) << message;
}

// Through the tools: exit 2 and the file named, nothing written.
TEST(MalformedJson, ToolsAnswerExit2NamingTheFile) {
  const fs::path dir = scratch_dir("json_limits");
  const fs::path cloud = fs::path(toolinc::testing::kSourceDir) / "data/held/hoe.ply";
  const std::vector<std::string> bad = {"{\"type\": \"tool_frame\", \"version\": 1e400}",
                                        "{\"deep\": " + nested(50000) + ", \"type\": \"tool_frame\"}"};
  for (std::size_t i = 0; i < bad.size(); ++i) {
    const fs::path frame = dir / ("frame" + std::to_string(i) + ".json");
    std::ofstream(frame) << bad[i];
    const ToolRun run =
        run_tool("find-tooltip", cloud.string() + " --frame " + frame.string() + " -o " + (dir / "tip.json").string());
    EXPECT_EQ(run.exit_code, 2) << run.err;
    expect_failure_left_nothing(run, frame.string(), dir / "tip.json", dir);
  }
  const fs::path config = dir / "config.json";
  std::ofstream(config) << "{\"samples\": " << nested(50000) << "}";
  const ToolRun run =
      run_tool("estimate-frame", cloud.string() + " -c " + config.string() + " -o " + (dir / "frame.json").string());
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("nested"), std::string::npos) << run.err;
}

// --- feature rows -------------------------------------------------------------------------------------

TEST(MalformedFeatureRows, RaggedRowsJunkAndEmptyFilesAreNamed) {
  const auto dir = scratch_dir("appearance-rows");
  write_text(dir / "ragged.txt", "1 2 3\n\n4 5 6\n7 8\n");
  write_text(dir / "junk.txt", "1 2 x3\n");
  write_text(dir / "empty.txt", "\n \n");
  for (const auto& [file, words] :
       std::vector<std::pair<std::string, std::string>>{{"ragged.txt", "line 4: 2 values, but the first row has 3"},
                                                        {"junk.txt", "line 1"},
                                                        {"empty.txt", "no feature"}}) {
    try {
      read_feature_rows((dir / file).string());
      ADD_FAILURE() << file << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find((dir / file).string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace toolinc
