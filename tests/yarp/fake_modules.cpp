// toolinc-yarp-fakes SESSION [VIEW] [--static-poses FILE]: stands in for the iCub's camera, stereo module
// and blob detector on a YARP network, publishing one recorded view (e.g. from `record --backend sim`)
// as they would: the left image, the 8-bit disparity, the blob mask, ROI and centroid at 10 Hz, and the
// stereo module's `Rect tlx tly w h step` RPC answered from the view's points.pcd (0 0 0 where it has
// none). With --static-poses it also writes the view's poses and camera for `record --static-poses`.
// For the loopback check of record's YARP adapter (scripts/yarp-loopback.sh); runs until SIGINT/SIGTERM.
#include <yarp/os/Bottle.h>
#include <yarp/os/BufferedPort.h>
#include <yarp/os/Network.h>
#include <yarp/os/RpcServer.h>
#include <yarp/os/Time.h>
#include <yarp/sig/Image.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <thread>

#include "toolinc/io/json_file.hpp"
#include "toolinc/session/session.hpp"

namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop = true; }

template <typename Pixel>
void fill(yarp::sig::ImageOf<Pixel>& image, const cv::Mat& mat) {
  image.resize(mat.cols, mat.rows);
  for (int v = 0; v < mat.rows; ++v)
    for (int u = 0; u < mat.cols; ++u) {
      if constexpr (std::is_same_v<Pixel, yarp::sig::PixelRgb>) {
        const cv::Vec3b bgr = mat.at<cv::Vec3b>(v, u);
        image.pixel(u, v) = yarp::sig::PixelRgb(bgr[2], bgr[1], bgr[0]);
      } else {
        image.pixel(u, v) = mat.at<uchar>(v, u);
      }
    }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: toolinc-yarp-fakes SESSION [VIEW] [--static-poses FILE]\n");
    return 2;
  }
  const std::string session_dir = argv[1];
  std::size_t view = 0;
  std::string static_poses;
  for (int i = 2; i < argc; ++i) {
    if (std::strcmp(argv[i], "--static-poses") == 0 && i + 1 < argc)
      static_poses = argv[++i];
    else
      view = std::stoul(argv[i]);
  }
  try {
    const toolinc::SessionInfo session = toolinc::read_session(session_dir);
    const toolinc::ViewData data = toolinc::read_view(session_dir, session, view);
    const toolinc::ViewRecord& record = session.views.at(view);
    if (!record.blob || data.blob.empty() || data.points.empty()) {
      std::fprintf(stderr, "toolinc-yarp-fakes: %s view %zu has no blob or no points.pcd\n", session_dir.c_str(), view);
      return 2;
    }
    if (!static_poses.empty()) {
      const toolinc::CameraModel& c = session.camera;
      toolinc::write_json(
          static_poses,
          {{"root_from_hand", toolinc::to_json(record.root_from_hand)},
           {"root_from_camera", toolinc::to_json(record.root_from_camera)},
           {"camera",
            {{"width", c.width}, {"height", c.height}, {"fx", c.fx}, {"fy", c.fy}, {"cx", c.cx}, {"cy", c.cy}}}});
    }

    yarp::os::Network network;
    if (!yarp::os::Network::checkNetwork(5.0)) {
      std::fprintf(stderr, "toolinc-yarp-fakes: no YARP name server\n");
      return 2;
    }
    std::signal(SIGINT, on_signal);
    std::signal(SIGTERM, on_signal);
    yarp::os::BufferedPort<yarp::sig::ImageOf<yarp::sig::PixelRgb>> left;
    yarp::os::BufferedPort<yarp::sig::ImageOf<yarp::sig::PixelMono>> disparity, mask;
    yarp::os::BufferedPort<yarp::os::Bottle> roi, blobs;
    yarp::os::RpcServer sfm;
    if (!left.open("/icub/camcalib/left/out") || !disparity.open("/SFM/disp:o") || !mask.open("/dispBlobber/opt:o") ||
        !roi.open("/dispBlobber/roi/left:o") || !blobs.open("/dispBlobber/blobs/left:o") || !sfm.open("/SFM/rpc")) {
      std::fprintf(stderr, "toolinc-yarp-fakes: cannot open the ports\n");
      return 2;
    }

    // SFM's Rect: u outer, v inner, X Y Z per pixel, 0 0 0 where there is no depth.
    std::thread rpc([&] {
      while (!g_stop) {
        yarp::os::Bottle command, reply;
        if (!sfm.read(command, true)) continue;
        if (command.get(0).asString() == "Rect" && command.size() >= 5) {
          const int x = command.get(1).asInt32(), y = command.get(2).asInt32(), w = command.get(3).asInt32(),
                    h = command.get(4).asInt32(), step = command.size() >= 6 ? command.get(5).asInt32() : 1;
          for (int u = x; u < x + w; u += step)
            for (int v = y; v < y + h; v += step) {
              const bool inside = u >= 0 && v >= 0 && u < session.camera.width && v < session.camera.height;
              const auto& p = inside ? data.points[static_cast<std::size_t>(v) * session.camera.width + u]
                                     : toolinc::Vec3(NAN, NAN, NAN);
              for (int k = 0; k < 3; ++k) reply.addFloat64(p.allFinite() ? p[k] : 0.0);
            }
        } else {
          reply.addVocab32('n', 'a', 'c', 'k');
        }
        sfm.reply(reply);
      }
    });

    const toolinc::BlobInfo& b = *record.blob;
    std::fprintf(stderr, "toolinc-yarp-fakes: publishing %s view %zu\n", session_dir.c_str(), view);
    while (!g_stop) {
      fill(left.prepare(), data.left);
      left.write();
      fill(disparity.prepare(), data.disparity);
      disparity.write();
      fill(mask.prepare(), data.blob);
      mask.write();
      yarp::os::Bottle& r = roi.prepare();
      r.clear();
      yarp::os::Bottle& box = r.addList();
      for (int k = 0; k < 4; ++k) box.addInt32(b.roi[k]);
      roi.write();
      yarp::os::Bottle& c = blobs.prepare();
      c.clear();
      yarp::os::Bottle& blob = c.addList();
      blob.addInt32(static_cast<int>(b.cx)), blob.addInt32(static_cast<int>(b.cy)),
          blob.addInt32(static_cast<int>(b.area));
      blobs.write();
      yarp::os::Time::delay(0.1);
    }
    sfm.interrupt();
    rpc.join();
    for (auto* port : {static_cast<yarp::os::Contactable*>(&left), static_cast<yarp::os::Contactable*>(&disparity),
                       static_cast<yarp::os::Contactable*>(&mask), static_cast<yarp::os::Contactable*>(&roi),
                       static_cast<yarp::os::Contactable*>(&blobs), static_cast<yarp::os::Contactable*>(&sfm)})
      port->close();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "toolinc-yarp-fakes: %s\n", e.what());
    return 2;
  }
  return 0;
}
