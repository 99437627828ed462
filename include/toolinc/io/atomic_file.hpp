// Outputs appear whole or not at all: written to a temporary file in the destination's folder, synced,
// then renamed over it, and the folder synced, so that neither a crash nor a power loss leaves a partial
// file (only the old one or the new one). "-" means standard output.
#pragma once

#include <functional>
#include <ostream>
#include <string>

namespace toolinc {

// Calls write(stream) on a temporary file next to path, then renames it to path. On any exception the
// temporary file is removed and the exception propagates; path is left untouched.
void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& write, bool binary = false);

// fsync of a file or folder (so that what was written or renamed there is on disk); throws
// InputError(reported, "cannot sync: ...").
void sync_path(const std::string& path, const std::string& reported);
// sync_path of the folder holding path (after a rename or a file creation in it).
void sync_folder_of(const std::string& path);

// Outputs of one run that appear together or not at all (e.g. crop-cloud --all's one PLY per view):
// files go into a temporary folder beside `dir` (path(name)); commit() renames it to `dir` when `dir`
// does not exist or is empty, or else moves the files into `dir` one by one (each atomic, the set only
// once all were written). Destroyed without commit(), it removes the temporary folder: nothing is left.
class OutputFolder {
 public:
  explicit OutputFolder(const std::string& dir);
  ~OutputFolder();
  OutputFolder(const OutputFolder&) = delete;
  OutputFolder& operator=(const OutputFolder&) = delete;

  std::string path(const std::string& name) const;
  void commit();

 private:
  std::string dir_, temp_;
  bool committed_ = false;
};

}  // namespace toolinc
