#include "toolinc/io/atomic_file.hpp"

#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "toolinc/core/error.hpp"
#include "toolinc/io/run_inputs.hpp"

namespace toolinc {
namespace {

// The pid keeps concurrent processes apart, the counter concurrent writes within one process.
std::string temp_path_for(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
}

// The pid in "<name>.tmp.<pid>" (a folder) or "<name>.tmp.<pid>.<n>" (a file), 0 for other names.
pid_t temp_owner(const std::string& entry, const std::string& name) {
  const std::string prefix = name + ".tmp.";
  if (entry.compare(0, prefix.size(), prefix) != 0) return 0;
  const std::string rest = entry.substr(prefix.size());
  const std::size_t dot = rest.find('.');
  const std::string pid = rest.substr(0, dot), counter = dot == std::string::npos ? "" : rest.substr(dot + 1);
  const auto digits = [](const std::string& s) {
    return !s.empty() && s.size() < 10 && s.find_first_not_of("0123456789") == std::string::npos;
  };
  if (!digits(pid) || (dot != std::string::npos && !digits(counter))) return 0;
  return static_cast<pid_t>(std::stol(pid));
}

bool process_is_gone(pid_t pid) { return ::kill(pid, 0) != 0 && errno == ESRCH; }

// A writer killed between creating its temporary file (or folder) and renaming it leaves it behind;
// the next write of the same target removes those whose process no longer exists. Live writers' ones,
// this process's and anything named otherwise are left alone.
void remove_stale_temps(const std::string& target) {
  namespace fs = std::filesystem;
  const fs::path path(target);
  const fs::path parent = path.parent_path().empty() ? fs::path(".") : path.parent_path();
  const std::string name = path.filename().string();
  std::error_code ec;
  for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
    const pid_t pid = temp_owner(it->path().filename().string(), name);
    if (pid > 0 && pid != ::getpid() && process_is_gone(pid)) {
      std::error_code ignored;
      fs::remove_all(it->path(), ignored);
    }
  }
}

// Streams do not always set errno (a writer may set failbit itself), so avoid reporting "Success".
std::string last_error() { return errno != 0 ? std::strerror(errno) : "I/O error"; }

void write_to_stdout(const std::function<void(std::ostream&)>& write) {
  write(std::cout);
  std::cout.flush();
  if (!std::cout) throw InputError("-", "cannot write: " + last_error());
}

// Writes, flushes, closes and syncs the temporary file, renames it over path, then syncs the folder so
// the rename itself survives a power loss.
void write_and_rename(std::ofstream& out, const std::string& temp, const std::string& path,
                      const std::function<void(std::ostream&)>& write) {
  errno = 0;
  write(out);
  out.flush();
  if (!out) throw InputError(path, "cannot write: " + last_error());
  out.close();
  if (!out) throw InputError(path, "cannot write: " + last_error());
  sync_path(temp, path);
  if (std::rename(temp.c_str(), path.c_str()) != 0) throw InputError(path, "cannot write: " + last_error());
  sync_folder_of(path);
}

}  // namespace

void sync_path(const std::string& path, const std::string& reported) {
  // fsync needs a descriptor but not a writable one; O_RDONLY opens folders too.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  const bool ok = fd >= 0 && ::fsync(fd) == 0;
  const std::string error = ok ? "" : last_error();
  if (fd >= 0) ::close(fd);
  if (!ok) throw InputError(reported, "cannot sync: " + error);
}

void sync_folder_of(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  sync_path(parent.empty() ? "." : parent.string(), path);
}

void write_file_atomic(const std::string& path, const std::function<void(std::ostream&)>& write, bool binary) {
  if (path == "-") return write_to_stdout(write);
  check_not_an_input(path);
  remove_stale_temps(path);
  const std::string temp = temp_path_for(path);
  errno = 0;
  std::ofstream out(temp, binary ? std::ios::out | std::ios::binary : std::ios::out);
  if (!out) throw InputError(path, "cannot write: " + last_error());
  try {
    write_and_rename(out, temp, path, write);
  } catch (...) {
    out.close();
    std::remove(temp.c_str());
    throw;
  }
}

namespace {

// "out/" and "out" are the same folder; the temporary one goes beside it, not inside.
std::string without_trailing_slash(const std::string& dir) {
  std::filesystem::path path = std::filesystem::path(dir).lexically_normal();
  if (!path.has_filename() && path.has_parent_path()) path = path.parent_path();
  return path.string();
}

template <class F>
void as_input_error(const std::string& dir, F&& f) {
  try {
    f();
  } catch (const std::filesystem::filesystem_error& e) {
    throw InputError(dir, "cannot write: " + e.code().message());
  }
}

}  // namespace

OutputFolder::OutputFolder(const std::string& dir)
    : dir_(without_trailing_slash(dir)), temp_(dir_ + ".tmp." + std::to_string(::getpid())) {
  check_not_an_input(dir_);
  remove_stale_temps(dir_);
  as_input_error(dir, [&] {
    std::filesystem::remove_all(temp_);
    std::filesystem::create_directories(temp_);
  });
}

OutputFolder::~OutputFolder() {
  std::error_code ignored;
  if (!committed_) std::filesystem::remove_all(temp_, ignored);
}

std::string OutputFolder::path(const std::string& name) const { return (std::filesystem::path(temp_) / name).string(); }

void OutputFolder::commit() {
  namespace fs = std::filesystem;
  as_input_error(dir_, [&] {
    std::error_code ec;
    if (fs::exists(dir_, ec) && !fs::is_directory(dir_, ec)) throw InputError(dir_, "exists and is not a folder");
    // Each file was synced by write_file_atomic; what is left to make durable is the renames.
    if (!fs::exists(dir_, ec) || fs::is_empty(dir_, ec)) {
      fs::rename(temp_, dir_);  // replaces an empty folder too
    } else {
      for (const auto& entry : fs::directory_iterator(temp_))
        check_not_an_input((fs::path(dir_) / entry.path().filename()).string());
      for (const auto& entry : fs::directory_iterator(temp_))
        fs::rename(entry.path(), fs::path(dir_) / entry.path().filename());
      sync_path(dir_, dir_);
      fs::remove(temp_);
    }
    sync_folder_of(dir_);
  });
  committed_ = true;
}

}  // namespace toolinc
