// An outside tester's findings on hostile inputs, one test per finding, each with fixtures made here:
// outputs that name an input, devices and FIFOs, sessions linked outside their folder, absurd
// coordinates, non-finite options, ill-typed JSON, duplicated views, temporary files of killed writers,
// messages that must name the file, and options, session paths and models beyond their physical range. Malformed and
// lying files of every reader: test_malformed_files.cpp.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstring>
#include <fstream>
#include <sstream>

#include "support/input_error_of.hpp"
#include "support/paths.hpp"
#include "support/run_tool.hpp"
#include "toolinc/cloud/preprocessing.hpp"
#include "toolinc/core/error.hpp"
#include "toolinc/io/atomic_file.hpp"
#include "toolinc/io/cloud_io.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/io/limits.hpp"
#include "toolinc/io/read_file.hpp"
#include "toolinc/session/session.hpp"
#include "toolinc/synth/session_simulator.hpp"

using namespace toolinc;
using namespace toolinc::testing;
namespace fs = std::filesystem;

namespace {

const fs::path kHoe = fs::path(toolinc::testing::kSourceDir) / "data/held/hoe.ply";
const fs::path kHoeTruth = fs::path(toolinc::testing::kSourceDir) / "data/held/hoe.truth.json";

std::string q(const fs::path& path) { return "'" + path.string() + "'"; }

// Exit 2, one error line naming `word`, nothing left at `output`, and `input` unchanged.
void expect_refused(const ToolRun& run, const std::string& word, const fs::path& input, const std::string& before) {
  EXPECT_EQ(run.exit_code, 2) << run.err;
  std::istringstream lines(run.err);
  int errors = 0, lines_total = 0;
  for (std::string line; std::getline(lines, line); ++lines_total) {
    if (line.find(": error: ") == std::string::npos) continue;
    ++errors;
    EXPECT_NE(line.find(word), std::string::npos) << line;
  }
  EXPECT_EQ(errors, 1) << run.err;
  if (!input.empty()) EXPECT_EQ(slurp(input), before) << input << " was modified";
}

SimulatedSession small_session(std::uint32_t seed) { return simulate_session(family_session(ToolFamily::hoe, seed)); }

fs::path copy_of(const fs::path& from, const fs::path& to) {
  fs::copy_file(from, to, fs::copy_options::overwrite_existing);
  return to;
}

// --- -o naming an input ---------------------------------------------------------------------------

TEST(OutputGuard, AnOutputThatIsAnInputIsRefusedAndTheInputKept) {
  const fs::path dir = scratch_dir("output_guard");
  const fs::path a = copy_of(kHoe, dir / "a.ply"), b = copy_of(kHoe, dir / "b.ply");
  const fs::path truth = copy_of(kHoeTruth, dir / "t.json");
  const std::string cloud = slurp(a), truth_text = slurp(truth);
  fs::create_symlink(a, dir / "link.ply");
  fs::create_hard_link(a, dir / "hard.ply");
  std::ofstream(dir / "c.json") << "{\"type\": \"classifier\"}";
  const struct {
    std::string tool, args;
    fs::path input;
    const std::string& before;
  } cases[] = {
      {"estimate-frame", q(a) + " -o " + q(a), a, cloud},
      {"estimate-frame", q(a) + " -o " + q(dir / "." / "a.ply"), a, cloud},
      {"estimate-frame", q(a) + " -o " + q(dir / "link.ply"), a, cloud},
      {"estimate-frame", q(a) + " -o " + q(dir / "hard.ply"), a, cloud},
      {"merge-views", q(a) + " " + q(b) + " -o " + q(a), a, cloud},
      {"render", q(a) + " -o " + q(a), a, cloud},
      {"evaluate", "--truth " + q(truth) + " -o " + q(truth), truth, truth_text},
      {"learn-appearance",
       "classify --classifier " + q(dir / "c.json") + " --features " + q(a) + " -o " + q(dir / "c.json"),
       dir / "c.json", "{\"type\": \"classifier\"}"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.tool + " " + c.args);
    const std::string shown = c.args.substr(c.args.rfind("-o '") + 4, c.args.size() - c.args.rfind("-o '") - 5);
    expect_refused(run_tool(c.tool, c.args), shown, c.input, c.before);
  }
  // An output inside a session that is read (crop-cloud writing over the session's own points).
  const SimulatedSession simulated = small_session(21);
  const fs::path session = dir / "session";
  write_session(session.string(), simulated.info, simulated.views);
  const fs::path inside = session / simulated.info.views[0].dir / "view.json";
  const std::string view = slurp(inside);
  expect_refused(run_tool("crop-cloud", q(session) + " --view 0 -o " + q(inside)), inside.string(), inside, view);
  for (const auto& entry : fs::directory_iterator(dir))
    EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << entry.path();
}

// --- unbounded reads -------------------------------------------------------------------------------

TEST(BoundedReader, DevicesFifosAndOversizedFilesAreRefused) {
  const fs::path dir = scratch_dir("bounded_reader");
  expect_refused(run_tool("estimate-frame", "/dev/zero -o " + q(dir / "f.json")), "/dev/zero", {}, "");
  fs::create_symlink("/dev/zero", dir / "zero.ply");
  const ToolRun linked = run_tool("estimate-frame", q(dir / "zero.ply") + " -o " + q(dir / "f.json"));
  expect_refused(linked, "zero.ply", {}, "");
  EXPECT_NE(linked.err.find("not a regular file"), std::string::npos) << linked.err;
  expect_refused(run_tool("estimate-frame", q(kHoe) + " -c /dev/zero -o " + q(dir / "f.json")), "/dev/zero", {}, "");
  EXPECT_FALSE(fs::exists(dir / "f.json"));

  // A session whose session.json, points.pcd or view.json is a device or a FIFO.
  const SimulatedSession simulated = small_session(22);
  const fs::path session = dir / "session";
  write_session(session.string(), simulated.info, simulated.views);
  const fs::path view = session / simulated.info.views[0].dir;
  fs::remove(view / "points.pcd");
  fs::create_symlink("/dev/zero", view / "points.pcd");
  expect_refused(run_tool("crop-cloud", q(session) + " -o " + q(dir / "c.ply")), "points.pcd", {}, "");
  fs::remove(view / "view.json");
  ASSERT_EQ(::mkfifo((view / "view.json").c_str(), 0600), 0) << std::strerror(errno);
  // No writer ever opens the FIFO: a reader that waits for one would hang here (ctest's timeout).
  expect_refused(run_tool("crop-cloud", q(session) + " -o " + q(dir / "c.ply")), "view.json", {}, "");
  fs::rename(session / "session.json", dir / "session.json");
  fs::create_symlink("/dev/zero", session / "session.json");
  expect_refused(run_tool("crop-cloud", q(session) + " -o " + q(dir / "c.ply")), "session.json", {}, "");

  std::ofstream(dir / "big.txt") << std::string(1000, 'x');
  const std::string big = input_error_of([&] { read_file((dir / "big.txt").string(), 999); });
  EXPECT_NE(big.find("big.txt: cannot read: 1000 bytes, more than the 999 allowed"), std::string::npos) << big;
  EXPECT_EQ(read_file((dir / "big.txt").string(), 1000).size(), 1000u);
}

// A left.png whose header declares 2 billion pixels a row: libpng printed two lines of its own before ours.
TEST(SessionImages, AnAbsurdPngHeaderIsOneLineOfOurs) {
  const fs::path dir = scratch_dir("huge_ihdr");
  const SimulatedSession simulated = small_session(23);
  const fs::path session = dir / "session";
  write_session(session.string(), simulated.info, simulated.views);
  const fs::path left = session / simulated.info.views[0].dir / "left.png";
  std::string png = slurp(left);
  ASSERT_EQ(png.compare(12, 4, "IHDR"), 0);
  png.replace(16, 4, std::string("\x77\x35\x94\x00", 4));  // width 2,000,000,000
  std::ofstream(left, std::ios::binary | std::ios::trunc) << png;
  const ToolRun run = run_tool("crop-cloud", q(session) + " --image-mask -o " + q(dir / "c.ply"));
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  expect_failure_left_nothing(run, "left.png is 2000000000x", dir / "c.ply", dir);
}

// --- sessions leaving their folder through links ---------------------------------------------------

TEST(SessionLinks, AViewFolderOrImageLinkedOutsideTheSessionIsRefused) {
  const fs::path root = scratch_dir("session_links");
  const SimulatedSession simulated = small_session(23);
  write_session((root / "other").string(), simulated.info, simulated.views);
  write_session((root / "s").string(), simulated.info, simulated.views);
  const std::string view0 = simulated.info.views[0].dir;
  fs::remove_all(root / "s" / view0);
  fs::create_directory_symlink(root / "other" / view0, root / "s" / view0);
  const std::string folder = input_error_of([&] { read_session((root / "s").string()); });
  EXPECT_NE(folder.find("outside the session folder"), std::string::npos) << folder;

  fs::remove(root / "s" / view0);
  fs::copy(root / "other" / view0, root / "s" / view0, fs::copy_options::recursive);
  fs::remove(root / "s" / view0 / "left.png");
  fs::create_symlink(root / "other" / view0 / "left.png", root / "s" / view0 / "left.png");
  const SessionInfo info = read_session((root / "s").string());
  const std::string image = input_error_of([&] { read_view((root / "s").string(), info, 0); });
  EXPECT_NE(image.find("left.png: resolves to"), std::string::npos) << image;
  EXPECT_NE(image.find("outside the session folder"), std::string::npos) << image;
  // A link that stays inside the session is the session's own data.
  fs::remove(root / "s" / view0 / "left.png");
  fs::create_symlink(fs::path("..") / fs::path(simulated.info.views[1].dir).filename() / "left.png",
                     root / "s" / view0 / "left.png");
  EXPECT_NO_THROW(read_view((root / "s").string(), info, 0));
}

// --- absurd coordinates ----------------------------------------------------------------------------

TEST(CoordinateRange, CloudsBeyondThePhysicalRangeAreRefusedNamingTheFile) {
  const fs::path dir = scratch_dir("coordinates");
  PointCloud cloud = read_cloud(kHoe.string());
  cloud.points[7] = Vec3(1e30, 0, 0);
  write_ply((dir / "far.ply").string(), cloud);
  const ToolRun run = run_tool("estimate-frame", q(dir / "far.ply") + " -o " + q(dir / "f.json"));
  expect_refused(run, "far.ply", {}, "");
  EXPECT_NE(run.err.find("point 7 at (1e+30, 0, 0) lies beyond the 1000 m"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(dir / "f.json"));
  std::ofstream(dir / "far.pcd")
      << "FIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nWIDTH 2\nPOINTS 2\nDATA ascii\n0 0 0\n0 -2e3 0\n";
  const std::string pcd = input_error_of([&] { read_cloud((dir / "far.pcd").string()); });
  EXPECT_NE(pcd.find("far.pcd: point 1"), std::string::npos) << pcd;
  // The voxel grid itself refuses cells its 64-bit keys cannot hold (e.g. a voxel of 1e-300 m).
  EXPECT_THROW(voxel_downsample({Vec3(0.1, 0, 0)}, 1e-300), std::invalid_argument);
}

// --- non-finite options ----------------------------------------------------------------------------

TEST(FiniteOptions, NanAndInfinityAreRefusedOnTheCommandLineAndInAConfig) {
  const fs::path dir = scratch_dir("finite_options");
  const std::string out = " -o " + q(dir / "f.json");
  for (const std::string& value : {"nan", "NaN", "inf", "-inf", "1e400"}) {
    expect_refused(run_tool("estimate-frame", q(kHoe) + " --symmetry-step-deg=" + value + out), "--symmetry-step-deg",
                   {}, "");
    expect_refused(run_tool("estimate-frame", q(kHoe) + " --voxel-size=" + value + out), "--voxel-size", {}, "");
    // Named as not finite, not as out of a range whose bound prints as 309 digits.
    const ToolRun run = run_tool("merge-views", q(kHoe) + " --max-translation=" + value + " -o " + q(dir / "m.ply"));
    expect_refused(run, "--max-translation", {}, "");
    EXPECT_NE(run.err.find("must be a finite number, not " + value), std::string::npos) << run.err;
  }
  std::ofstream(dir / "config.json") << "{\"symmetry-step-deg\": \"NaN\"}";
  const ToolRun config = run_tool("estimate-frame", q(kHoe) + " -c " + q(dir / "config.json") + out);
  expect_refused(config, (dir / "config.json").string(), {}, "");
  EXPECT_NE(config.err.find("--symmetry-step-deg"), std::string::npos) << config.err;
  EXPECT_FALSE(fs::exists(dir / "f.json"));
}

// Out of range, merge-views' options are refused too: a negative grid once merged every view into an
// empty model and exited 0.
TEST(FiniteOptions, MergeViewsRefusesOptionsOutOfTheirRange) {
  const fs::path dir = scratch_dir("merge_ranges");
  for (const std::string& option :
       {"--voxel-size=-1", "--voxel-size=0", "--max-translation=-0.1", "--max-rotation-deg=-5", "--min-inlier-ratio=7",
        "--min-points=-1", "--max-correspondence=0"}) {
    const ToolRun run = run_tool("merge-views", q(kHoe) + " " + option + " -o " + q(dir / "m.ply"));
    expect_refused(run, option.substr(0, option.find('=')), {}, "");
    EXPECT_FALSE(fs::exists(dir / "m.ply")) << option;
  }
}

// crop-cloud's and record's options come from their parameter tables, ranges included: no neighbours for
// the outlier statistics, a negative hand ball, a zero timeout or no attempt is refused before anything runs.
TEST(FiniteOptions, CropCloudAndRecordRefuseOptionsOutOfTheirRange) {
  const fs::path dir = scratch_dir("table_ranges");
  for (const std::string& option : {"--outlier-neighbors=0", "--outlier-std=0", "--hand-radius=-0.01", "--mask-band=-1",
                                    "--mask-surround=0", "--flood-distance=0"}) {
    const ToolRun run = run_tool("crop-cloud", q(dir / "no-session") + " " + option + " -o " + q(dir / "c.ply"));
    expect_refused(run, option.substr(0, option.find('=')), {}, "");
    EXPECT_FALSE(fs::exists(dir / "c.ply")) << option;
  }
  for (const std::string& option : {"--attempts=0", "--read-timeout=0", "--gaze-fraction=1.5", "--settle-time=-1",
                                    "--sfm-step=0", "--baseline=0"}) {
    const ToolRun run = run_tool("record", "--backend sim -q " + option + " -o " + q(dir / "session"));
    expect_refused(run, option.substr(0, option.find('=')), {}, "");
    EXPECT_FALSE(fs::exists(dir / "session")) << option;
  }
}

// --- ill-typed JSON --------------------------------------------------------------------------------

TEST(JsonTypes, ATruthWithAWronglyTypedFieldIsExit2NamingFileAndField) {
  const fs::path dir = scratch_dir("truth_types");
  const Json truth = read_json(kHoeTruth.string());
  for (const Json& symmetry : {Json(3), Json::array({1, 2}), Json(true), Json(nullptr), Json::object({{"a", 1}})}) {
    Json bad = truth;
    bad["symmetry"] = symmetry;
    write_json((dir / "t.json").string(), bad);
    const ToolRun run = run_tool("evaluate", "--truth " + q(dir / "t.json") + " -o -");
    SCOPED_TRACE(symmetry.dump());
    expect_refused(run, (dir / "t.json").string(), {}, "");
    EXPECT_NE(run.err.find("\"symmetry\""), std::string::npos) << run.err;
  }
}

// --- duplicated views ------------------------------------------------------------------------------

TEST(SessionViews, AViewListedTwiceIsRefused) {
  const fs::path root = scratch_dir("duplicate_views");
  const SimulatedSession simulated = small_session(24);
  const fs::path session = root / "s";
  write_session(session.string(), simulated.info, simulated.views);
  const std::string view0 = simulated.info.views[0].dir;
  for (const Json& views :
       {Json::array({view0, view0}), Json::array({view0, view0 + "/"}), Json::array({view0, "./" + view0})}) {
    Json json = read_json((session / "session.json").string());
    json["views"] = views;
    write_json((session / "session.json").string(), json);
    const std::string message = input_error_of([&] { read_session(session.string()); });
    EXPECT_NE(message.find("session.json: view folder"), std::string::npos) << message;
    EXPECT_NE(message.find("is listed twice"), std::string::npos) << message;
  }
}

// --- temporary files of killed writers -------------------------------------------------------------

pid_t a_dead_pid() {
  const pid_t child = ::fork();
  if (child == 0) ::_exit(0);
  ::waitpid(child, nullptr, 0);
  return child;
}

TEST(StaleTemps, ALaterWriteRemovesTheTemporaryFilesOfWritersThatAreGone) {
  const fs::path dir = scratch_dir("stale_temps");
  const std::string dead = std::to_string(a_dead_pid());
  const std::string alive = std::to_string(::getppid());
  for (const std::string& name :
       {"out.json.tmp." + dead + ".0", "out.json.tmp." + dead + ".17", "out.json.tmp." + alive + ".0",
        "other.json.tmp." + dead + ".0", "out.json.tmp." + dead + ".x"})
    std::ofstream(dir / name) << "partial";
  fs::create_directories(dir / ("views.tmp." + dead) / "sub");
  fs::create_directories(dir / ("views.tmp." + alive));
  write_json((dir / "out.json").string(), Json::object());
  EXPECT_FALSE(fs::exists(dir / ("out.json.tmp." + dead + ".0")));
  EXPECT_FALSE(fs::exists(dir / ("out.json.tmp." + dead + ".17")));
  EXPECT_TRUE(fs::exists(dir / ("out.json.tmp." + alive + ".0")));   // its writer may still rename it
  EXPECT_TRUE(fs::exists(dir / ("other.json.tmp." + dead + ".0")));  // another target's
  EXPECT_TRUE(fs::exists(dir / ("out.json.tmp." + dead + ".x")));    // not of this naming
  OutputFolder folder((dir / "views").string());
  EXPECT_FALSE(fs::exists(dir / ("views.tmp." + dead)));
  EXPECT_TRUE(fs::exists(dir / ("views.tmp." + alive)));
}

// Over `ulimit -f` the write fails (EFBIG) rather than SIGXFSZ killing the tool: exit 2, nothing left.
TEST(StaleTemps, AFileSizeLimitIsAWriteErrorThatLeavesNothing) {
  const fs::path dir = scratch_dir("file_size_limit");
  const std::string command = "ulimit -f 1; " + std::string(toolinc::testing::kBinDir) + "/estimate-frame -q " +
                              q(kHoe) + " -o " + q(dir / "f.json") + " 2>" + q(dir.parent_path() / "xfsz.err");
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status)) << "killed by a signal";
  EXPECT_EQ(WEXITSTATUS(status), 2) << slurp(dir.parent_path() / "xfsz.err");
  EXPECT_NE(slurp(dir.parent_path() / "xfsz.err").find("f.json: cannot write"), std::string::npos);
  EXPECT_TRUE(fs::is_empty(dir));
}

// --- messages naming the file ----------------------------------------------------------------------

TEST(Messages, UsageErrorsFromAConfigAndMethodFailuresAreOneLineNamingTheFile) {
  const fs::path dir = scratch_dir("messages");
  std::ofstream(dir / "config.json") << "{\"symmetry-step-deg\": 100}";
  const ToolRun config = run_tool("estimate-frame", q(kHoe) + " -c " + q(dir / "config.json") + " -o -");
  expect_refused(config, (dir / "config.json").string(), {}, "");
  EXPECT_EQ(std::count(config.err.begin(), config.err.end(), '\n'), 1) << config.err;
  // The same error on the command line is the command line's, not the config's.
  const ToolRun line =
      run_tool("estimate-frame", q(kHoe) + " -c " + q(dir / "config.json") + " --symmetry-step-deg 99 -o -");
  EXPECT_EQ(line.exit_code, 2);
  EXPECT_EQ(line.err.find(": error: " + (dir / "config.json").string()), std::string::npos) << line.err;

  // A method failure (too few points for a frame) names the cloud it failed on.
  PointCloud few;
  for (int i = 0; i < 5; ++i) few.points.emplace_back(0.1 + 0.01 * i, 0, 0);
  write_ply((dir / "few.ply").string(), few);
  const ToolRun method = run_tool("estimate-frame", q(dir / "few.ply") + " -o -");
  EXPECT_EQ(method.exit_code, 3) << method.err;
  EXPECT_NE(method.err.find(": error: " + (dir / "few.ply").string() + ": "), std::string::npos) << method.err;
}

}  // namespace

// --- physical ranges -------------------------------------------------------------------------------

namespace {

// A length finer than the resolution or longer than the workspace is refused by its option's name, with the
// config file's name when the value came from one, before anything runs.
TEST(PhysicalRanges, ALengthOutOfRangeIsRefusedOnTheCommandLineAndInAConfig) {
  const fs::path dir = scratch_dir("physical_ranges");
  const std::string out = " -o " + q(dir / "f.json");
  for (const auto& [value, bound] :
       {std::pair{"1e-300", "below 0.0001 m"}, std::pair{"1e308", "above 2 m"}, std::pair{"-0", "below 0.0001 m"}}) {
    const ToolRun line = run_tool("estimate-frame", q(kHoe) + " --voxel-size=" + std::string(value) + out);
    expect_refused(line, "--voxel-size: " + std::string(value) + " is " + bound, {}, "");
    EXPECT_EQ(line.err.find("config"), std::string::npos) << line.err;
    // The config's numbers reach the option as JSON prints them (1e308 as 1e+308).
    std::ofstream(dir / "config.json") << "{\"voxel-size\": " << value << "}";
    const ToolRun config = run_tool("estimate-frame", q(kHoe) + " -c " + q(dir / "config.json") + out);
    expect_refused(config, (dir / "config.json").string() + ": --voxel-size: ", {}, "");
    EXPECT_NE(config.err.find(bound), std::string::npos) << config.err;
  }
  // A count beyond memory, as a huge integer, from a config's section.
  std::ofstream(dir / "config.json") << "{\"estimate-frame\": {\"symmetry-samples\": 99999999999999999999}}";
  expect_refused(run_tool("estimate-frame", q(kHoe) + " -c " + q(dir / "config.json") + out), "--symmetry-samples", {},
                 "");
  EXPECT_FALSE(fs::exists(dir / "f.json"));
}

// A section length of 1e-300 m once made 1e298 sections (a crash), 1e-6 m a failed allocation and 1e-5 m a
// run of minutes: each is now a usage error at once.
TEST(PhysicalRanges, AVanishingHandleSectionIsExit2NotASignal) {
  const fs::path dir = scratch_dir("section_length");
  for (const std::string value : {"1e-300", "1e-10", "1e-6", "1e-5"}) {
    const auto start = std::chrono::steady_clock::now();
    const ToolRun run =
        run_tool("estimate-frame", q(kHoe) + " --handle-section-length " + value + " -o " + q(dir / "f.json"));
    expect_refused(run, "--handle-section-length: " + value + " is below 0.0001 m", {}, "");
    EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10)) << value;
  }
}

// A view entry longer than a path may be, with a name longer than a file name may be, or holding a NUL
// was handed to the file system, whose "File name too long" named neither the session nor the entry.
TEST(SessionPaths, AnOverlongOrNulViewEntryIsRefusedNamingTheSessionAndTheEntry) {
  const fs::path root = scratch_dir("session_long_paths");
  const SimulatedSession simulated = small_session(13);
  write_session((root / "s").string(), simulated.info, simulated.views);
  const fs::path file = root / "s/session.json";
  const Json original = read_json(file.string());
  for (const auto& [entry, reason] :
       {std::pair{std::string(200000, 'a'), std::string("is 200000 characters long")},
        std::pair{"views/" + std::string(300, 'b'), std::string("has a name of 300 characters")},
        std::pair{std::string("views/0\0"
                              "00",
                              10),
                  std::string("holds a NUL character")}}) {
    Json json = original;
    json["views"][1] = entry;
    write_json(file.string(), json);
    const std::string message = input_error_of([&] { read_session((root / "s").string()); });
    EXPECT_NE(message.find(file.string() + ": \"views\"[1] " + reason), std::string::npos) << message.substr(0, 300);
  }
  Json json = original;
  json["views"][0] = std::string(200000, 'a');
  write_json(file.string(), json);
  const std::string why = "\"views\"[0] is 200000 characters long";
  const ToolRun crop = run_tool("crop-cloud", q(root / "s") + " -o " + q(root / "c.ply"));
  expect_refused(crop, file.string() + ": " + why, {}, "");
  EXPECT_LT(crop.err.size(), 1000u);
  expect_refused(run_tool("render", "--session " + q(root / "s") + " -o " + q(root / "r.png")), why, {}, "");
  EXPECT_FALSE(fs::exists(root / "c.ply"));
  EXPECT_FALSE(fs::exists(root / "r.png"));
}

// A settling pause of 1e308 s hung record in 0.05 s steps after it had made the session folder.
TEST(RecordRanges, ATimeBeyondMinutesIsRefusedBeforeTheSessionFolder) {
  const fs::path dir = scratch_dir("record_ranges");
  std::ofstream(dir / "config.json") << "{\"record\": {\"settle-time\": 1e308}}";
  expect_refused(run_tool("record", "--backend sim -q -c " + q(dir / "config.json") + " -o " + q(dir / "session")),
                 (dir / "config.json").string() + ": --settle-time: 1e+308 is above 60 s", {}, "");
  for (const std::string option : {"--settle-time=61", "--arm-timeout=1e9", "--sim-real-time=2", "--attempts=1e6"}) {
    expect_refused(run_tool("record", "--backend sim -q " + option + " -o " + q(dir / "session")),
                   option.substr(0, option.find('=')), {}, "");
  }
  for (const auto& entry : fs::directory_iterator(dir)) EXPECT_EQ(entry.path().filename(), "config.json");
}

// A model no tool can be (a point, copies of one, a speck, millimetres) made a session whose true tooltip lay
// 95 m from the hand; it is refused as align-pose refuses it.
TEST(SimulateSessionModel, DegenerateAndMillimetreModelsAreRefusedWritingNothing) {
  const fs::path dir = scratch_dir("simulate_models");
  Points speck, millimetres;
  for (const Vec3& p : read_cloud(kHoe.string()).points) {
    speck.push_back(p * 1e-8);
    millimetres.push_back(p * 1000.0);
  }
  const std::vector<std::pair<std::string, Points>> models{{"one.ply", Points{Vec3(0.2, 0, 0)}},
                                                           {"same.ply", Points(10000, Vec3(0.2, 0.01, 0))},
                                                           {"speck.ply", speck},
                                                           {"mm.ply", millimetres}};
  for (const auto& [name, points] : models) {
    PointCloud cloud;
    cloud.points = points;
    write_ply((dir / name).string(), cloud);
    const ToolRun run = run_tool("simulate-session", "-q --model " + q(dir / name) + " -o " + q(dir / "session"));
    expect_refused(run, (dir / name).string() + ": the model", {}, "");
    EXPECT_FALSE(fs::exists(dir / "session")) << name;
    if (name == "mm.ply") EXPECT_NE(run.err.find("millimetres"), std::string::npos) << run.err;
  }
}

// A one-point view made align-pose call the healthy model "inf times larger than the view".
TEST(AlignPoseView, AOnePointViewIsBlamedNotTheModel) {
  const fs::path dir = scratch_dir("one_point_view");
  PointCloud one;
  one.points = {Vec3(0.2, 0, 0)};
  write_ply((dir / "one.ply").string(), one);
  const ToolRun run =
      run_tool("align-pose", "--model " + q(kHoe) + " --view " + q(dir / "one.ply") + " -o " + q(dir / "pose.json"));
  expect_refused(run, (dir / "one.ply").string() + ": the view spans 0 m", {}, "");
  EXPECT_EQ(run.err.find("the model"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(dir / "pose.json"));
}

}  // namespace
