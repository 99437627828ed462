#include "toolinc/io/run_inputs.hpp"

#include <sys/stat.h>

#include <filesystem>
#include <mutex>
#include <set>
#include <vector>

#include "toolinc/core/error.hpp"

namespace toolinc {
namespace {
namespace fs = std::filesystem;

struct Resolved {
  fs::path path;  // absolute, normal, links resolved as far as the path exists
  bool exists = false;
  dev_t device = 0;
  ino_t inode = 0;
};

Resolved resolve(const std::string& path) {
  Resolved r;
  std::error_code ec;
  r.path = fs::weakly_canonical(fs::absolute(path, ec), ec);
  if (ec) r.path = fs::absolute(path).lexically_normal();
  struct stat st {};
  if (::stat(path.c_str(), &st) == 0) {
    r.exists = true;
    r.device = st.st_dev;
    r.inode = st.st_ino;
  }
  return r;
}

bool same_file(const Resolved& a, const Resolved& b) {
  return a.path == b.path || (a.exists && b.exists && a.device == b.device && a.inode == b.inode);
}

bool is_inside(const fs::path& path, const fs::path& folder) {
  auto p = path.begin();
  for (auto f = folder.begin(); f != folder.end(); ++f, ++p) {
    if (f->empty()) continue;  // a trailing separator
    if (p == path.end() || *p != *f) return false;
  }
  return true;
}

}  // namespace

std::string resolved_path(const std::string& path) { return resolve(path).path.string(); }

bool resolves_inside(const std::string& path, const std::string& folder) {
  return is_inside(resolve(path).path, resolve(folder).path);
}

namespace {

struct Noted {
  std::vector<std::pair<std::string, Resolved>> list;  // in the order read
  std::set<fs::path> paths;
};

struct Inputs {
  std::mutex mutex;  // parallel jobs read concurrently
  bool tracking = false;
  Noted files, folders;
};

Inputs& inputs() {
  static Inputs instance;
  return instance;
}

void add(Noted& noted, const std::string& path) {
  Resolved r = resolve(path);
  if (noted.paths.insert(r.path).second) noted.list.emplace_back(path, std::move(r));
}

}  // namespace

void track_inputs() {
  std::lock_guard lock(inputs().mutex);
  inputs().tracking = true;
}

void note_input(const std::string& path) {
  std::lock_guard lock(inputs().mutex);
  if (inputs().tracking) add(inputs().files, path);
}

void note_input_folder(const std::string& dir) {
  std::lock_guard lock(inputs().mutex);
  if (inputs().tracking) add(inputs().folders, dir);
}

void check_not_among(const std::string& output, const std::vector<std::string>& files) {
  if (output.empty() || output == "-") return;
  const Resolved out = resolve(output);
  for (const auto& file : files)
    if (file != "-" && same_file(out, resolve(file)))
      throw InputError(output, "is also given as " + file + "; an output never replaces another file of the run");
}

void check_not_an_input(const std::string& output) {
  if (output.empty() || output == "-") return;
  const Resolved out = resolve(output);
  std::lock_guard lock(inputs().mutex);
  for (const auto& [given, input] : inputs().files.list)
    if (same_file(out, input))
      throw InputError(output, "is also an input of this run (" + given + "); inputs are never overwritten");
  for (const auto& [given, folder] : inputs().folders.list)
    if (is_inside(out.path, folder.path))
      throw InputError(output, "lies inside the input folder " + given + "; inputs are never overwritten");
}

std::vector<std::string> run_inputs() {
  std::lock_guard lock(inputs().mutex);
  std::vector<std::string> given;
  for (const auto& entry : inputs().files.list) given.push_back(entry.first);
  return given;
}

}  // namespace toolinc
