// Progress of long runs (a merge of many views) as one line, redrawn in place, only when the stream is
// a terminal and info messages are logged (not with -q): logs, pipes and batch jobs stay clean.
#pragma once

#include <cstddef>
#include <cstdio>
#include <functional>
#include <string>

namespace toolinc {

class Progress {
 public:
  explicit Progress(std::string label, std::FILE* stream = stderr);

  // "label: done/total (percent)"; the line is erased once done reaches total, so the log goes on on a
  // clean line. Usable as a std::function<void(std::size_t, std::size_t)>.
  void operator()(std::size_t done, std::size_t total) const;

  bool enabled() const { return enabled_; }

 private:
  std::string label_;
  std::FILE* stream_;
  bool enabled_;
};

// Runs body(i) for every i < count on `jobs` threads (the caller's among them), drawing the progress line.
// Each i is run once, in no set order: a body that writes only its own slot gives the same result for
// any number of jobs.
void run_in_parallel(std::size_t count, unsigned jobs, const Progress& progress,
                     const std::function<void(std::size_t)>& body);

}  // namespace toolinc
