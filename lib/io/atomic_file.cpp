#include "toolinc/io/atomic_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "toolinc/core/error.hpp"

namespace toolinc {
namespace {

// The pid keeps concurrent processes apart, the counter concurrent writes within one process.
std::string temp_path_for(const std::string& path) {
  static std::atomic<unsigned> counter{0};
  return path + ".tmp." + std::to_string(::getpid()) + "." + std::to_string(counter++);
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
      for (const auto& entry : fs::directory_iterator(temp_)) fs::rename(entry.path(), fs::path(dir_) / entry.path().filename());
      sync_path(dir_, dir_);
      fs::remove(temp_);
    }
    sync_folder_of(dir_);
  });
  committed_ = true;
}

std::string read_file(const std::string& path) {
  std::error_code ignored;
  // An ifstream opens a directory without complaint and then reads nothing.
  if (std::filesystem::is_directory(path, ignored)) throw InputError(path, "cannot open: Is a directory");
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, "cannot open: " + last_error());
  std::string data;
  const auto size = std::filesystem::file_size(path, ignored);
  if (!ignored) data.reserve(size);
  // Chunked reads work for pipes too, where the size is not known up front.
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) data.append(chunk, static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw InputError(path, "cannot read: " + last_error());
  return data;
}

}  // namespace toolinc
