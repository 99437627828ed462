// A session's files on arbitrary bytes, one target per file (TOOLINC_FUZZ_SESSION_FILE, set by CMake):
// session.json, view.json, left.png, disparity.png, blob.png. The other files of the session are a
// valid one-view 8x6 session written once; the input replaces just the fuzzed file, then the session
// and its view are read as every tool reads them.
#include <opencv2/core.hpp>

#include "fuzz_input.hpp"
#include "toolinc/session/session.hpp"

namespace {

const std::filesystem::path& session_dir() {
  static const std::filesystem::path dir = [] {
    const auto path = toolinc::fuzz::scratch() / "session";
    std::filesystem::remove_all(path);
    toolinc::SessionInfo info;
    info.hand = "right";
    info.camera = {8, 6, 10.0, 10.0, 4.0, 3.0, 16, 0.07};
    toolinc::ViewRecord record;
    record.dir = "views/000";
    record.blob = toolinc::BlobInfo{4, 3, 6, {2, 2, 6, 5}};
    info.views.push_back(record);
    toolinc::ViewData view;
    view.left = cv::Mat(6, 8, CV_8UC3, cv::Scalar(10, 200, 30));
    view.disparity = cv::Mat(6, 8, CV_8UC1, cv::Scalar(40));
    view.blob = cv::Mat(6, 8, CV_8UC1, cv::Scalar(0));
    view.blob(cv::Rect(2, 2, 4, 3)).setTo(255);
    toolinc::write_session(path.string(), info, {view});
    return path;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string name = TOOLINC_FUZZ_SESSION_FILE;
  const auto& dir = session_dir();
  const auto file = name == "session.json" ? dir / name : dir / "views/000" / name;
  toolinc::fuzz::write_bytes(file, data, size);
  return toolinc::fuzz::expect_only_input_errors([&] {
    const toolinc::SessionInfo session = toolinc::read_session(dir.string());
    for (std::size_t v = 0; v < session.views.size(); ++v) toolinc::read_view(dir.string(), session, v);
  });
}
