// Hostile inputs found by review and fuzzing, each with the bytes that triggered it: session paths outside the
// session, crop-cloud --all's all-or-nothing output, a viewpoint inside the cloud, and writes that survive a
// writer killed between write and rename. Malformed JSON (nesting, numbers): test_malformed_files.cpp.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <random>
#include <thread>

#include "cloud/free_space.hpp"
#include "support/input_error_of.hpp"
#include "support/run_tool.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/atomic_file.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/io/read_file.hpp"
#include "toolinc/session/session.hpp"
#include "toolinc/synth/session_simulator.hpp"

using namespace toolinc;
using namespace toolinc::testing;
namespace fs = std::filesystem;

namespace {

SimulatedSession small_session(std::uint32_t seed) { return simulate_session(family_session(ToolFamily::hoe, seed)); }

TEST(SessionPaths, ViewsOutsideTheSessionAreRejected) {
  const fs::path root = scratch_dir("session_paths");
  const SimulatedSession simulated = small_session(11);
  write_session((root / "other").string(), simulated.info, simulated.views);
  for (const std::string& outside : {std::string("../other/views/000"), std::string("views/../../other/views/000"),
                                     (root / "other/views/000").string(), std::string("")}) {
    const fs::path dir = root / "s";
    fs::remove_all(dir);
    fs::copy(root / "other", dir, fs::copy_options::recursive);
    Json json = read_json((dir / "session.json").string());
    json["views"] = Json::array({outside});
    write_json((dir / "session.json").string(), json);
    const std::string message = input_error_of([&] { read_session(dir.string()); });
    EXPECT_NE(message.find("session.json"), std::string::npos) << message;
    EXPECT_NE(message.find("not a relative path inside the session folder"), std::string::npos) << message;
  }
}

// A later view's truncated left.png used to leave view_000..003.ply behind (and empty folders on exit 3).
TEST(CropCloudAll, AFailedRunLeavesNoneOfItsOutputs) {
  const fs::path root = scratch_dir("crop_all");
  const SimulatedSession simulated = small_session(12);
  const fs::path session = root / "session";
  write_session(session.string(), simulated.info, simulated.views);
  const fs::path last = session / simulated.info.views.back().dir / "left.png";
  const std::string png = slurp(last);
  std::ofstream(last, std::ios::binary | std::ios::trunc) << png.substr(0, png.size() / 2);
  const ToolRun run = run_tool("crop-cloud", session.string() + " --all -o " + (root / "views").string());
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("left.png"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(root / "views"));
  for (const auto& entry : fs::directory_iterator(root)) EXPECT_EQ(entry.path().filename(), "session");

  // Whole again: every view appears, in a new folder or added to an existing one.
  std::ofstream(last, std::ios::binary | std::ios::trunc) << png;
  ASSERT_EQ(run_tool("crop-cloud", session.string() + " --all -q -o " + (root / "views").string()).exit_code, 0);
  fs::create_directories(root / "existing");
  std::ofstream(root / "existing/keep.txt") << "mine";
  ASSERT_EQ(run_tool("crop-cloud", session.string() + " --all -q -o " + (root / "existing").string()).exit_code, 0);
  for (std::size_t v = 0; v < simulated.info.views.size(); ++v) {
    const std::string name = "view_00" + std::to_string(v) + ".ply";
    EXPECT_TRUE(fs::exists(root / "views" / name)) << name;
    EXPECT_EQ(read_cloud((root / "views" / name).string()).points,
              read_cloud((root / "existing" / name).string()).points)
        << name;
  }
  EXPECT_EQ(slurp(root / "existing/keep.txt"), "mine");
  for (const auto& entry : fs::directory_iterator(root))
    EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << entry.path();
}

TEST(OutputFolder, NothingWithoutCommit) {
  const fs::path root = scratch_dir("output_folder");
  {
    OutputFolder folder((root / "out/").string());
    write_file_atomic(folder.path("a.txt"), [](std::ostream& out) { out << "a"; });
  }
  EXPECT_TRUE(fs::is_empty(root));
  OutputFolder folder((root / "out").string());
  write_file_atomic(folder.path("a.txt"), [](std::ostream& out) { out << "a"; });
  folder.commit();
  EXPECT_EQ(slurp(root / "out/a.txt"), "a");
  EXPECT_EQ(std::distance(fs::directory_iterator(root), fs::directory_iterator()), 1);
}

// A writer killed at random moments while rewriting a file: the file is always one whole version.
TEST(AtomicWrite, AWriterKilledMidWayLeavesTheOldOrTheNewFile) {
  const fs::path dir = scratch_dir("atomic_kill");
  const std::string target = (dir / "session.json").string();
  // Version k: a line "k n" then n copies of the letter for k, so a partial file cannot pass for whole.
  const auto version = [](int k) {
    const std::size_t n = 200000 + 7919 * static_cast<std::size_t>(k % 50);
    return std::to_string(k) + " " + std::to_string(n) + "\n" + std::string(n, static_cast<char>('a' + k % 26));
  };
  write_file_atomic(target, [&](std::ostream& out) { out << version(0); });
  std::mt19937 random(19);
  std::uniform_int_distribution<int> delay_us(0, 20000);
  for (int trial = 0; trial < 20; ++trial) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      for (int k = 1;; ++k) write_file_atomic(target, [&](std::ostream& out) { out << version(k); });
    }
    std::this_thread::sleep_for(std::chrono::microseconds(delay_us(random)));
    ::kill(child, SIGKILL);
    int status = 0;
    ::waitpid(child, &status, 0);
    const std::string text = read_file(target);
    const int k = std::stoi(text.substr(0, text.find(' ')));
    EXPECT_EQ(text, version(k)) << "trial " << trial << ": a partial file of " << text.size() << " bytes";
  }
  // The writer's own failure between write and rename (e.g. a full disk): the old file, no temporary.
  const std::string before = read_file(target);
  EXPECT_THROW(write_file_atomic(target,
                                 [](std::ostream& out) {
                                   out << "half";
                                   out.setstate(std::ios::badbit);
                                 }),
               InputError);
  EXPECT_EQ(read_file(target), before);
}

// A viewpoint inside the cloud asked for a 9.2 GB image (bad_alloc, or 0.5-2.5 GB and seconds for random
// ones); the sensor's field of view now bounds every image.
TEST(FreeSpaceBounds, ViewpointInsideTheCloudIsBounded) {
  Points cloud;
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  for (int i = 0; i < 20000; ++i) cloud.emplace_back(u(random), 2 * u(random), u(random));
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Vec3 centroid = Vec3::Zero();
  for (const auto& p : cloud) centroid += p;
  centroid /= static_cast<double>(cloud.size());
  const Points viewpoints{{0.001, 0.002, 0.0005}, centroid, {nan, 0, 0}, {0.0, 0.0, 0.5}};
  const FreeSpace free_space(cloud, viewpoints);
  // Two usable viewpoints (the centroid and NaN ones have no direction), each at most 241 x 241 pixels.
  EXPECT_EQ(free_space.views(), 2u);
  EXPECT_LE(free_space.pixels(), 2u * 241u * 241u);
  // Still evidence where it should be: from z = 0.5 m the space in front of the cloud was seen empty,
  // the space behind its near face was not.
  const FreeSpace outside(cloud, {{0.0, 0.0, 0.5}});
  EXPECT_TRUE(outside.seen({0.0, 0.0, 0.3}));
  EXPECT_FALSE(outside.seen({0.0, 0.0, -0.095}));
  EXPECT_FALSE(outside.seen({0.0, 0.0, 0.9}));  // behind the sensor
}

}  // namespace
