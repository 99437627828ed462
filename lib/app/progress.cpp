#include "toolinc/app/progress.hpp"

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

namespace toolinc {

Progress::Progress(std::string label, std::FILE* stream)
    : label_(std::move(label)),
      stream_(stream),
      enabled_(::isatty(::fileno(stream)) == 1 && spdlog::should_log(spdlog::level::info)) {}

void Progress::operator()(std::size_t done, std::size_t total) const {
  if (!enabled_ || total == 0) return;
  // \r returns to the start of the line, \033[K erases what a longer previous line left.
  if (done >= total)
    std::fprintf(stream_, "\r\033[K");
  else
    std::fprintf(stream_, "\r%s: %zu/%zu (%.0f%%)\033[K", label_.c_str(), done, total, 100.0 * done / total);
  std::fflush(stream_);
}

void run_in_parallel(std::size_t count, unsigned jobs, const Progress& progress,
                     const std::function<void(std::size_t)>& body) {
  std::atomic<std::size_t> next{0}, done{0};
  std::mutex progress_mutex;
  const auto worker = [&] {
    for (std::size_t i; (i = next++) < count;) {
      body(i);
      const std::lock_guard<std::mutex> lock(progress_mutex);
      progress(++done, count);
    }
  };
  std::vector<std::thread> threads;
  for (unsigned t = 1; t < jobs; ++t) threads.emplace_back(worker);
  worker();
  for (auto& thread : threads) thread.join();
}

}  // namespace toolinc
