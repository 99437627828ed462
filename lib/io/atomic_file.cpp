#include "toolinc/io/atomic_file.hpp"

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

// Writes, flushes and closes the temporary file, then renames it over path.
void write_and_rename(std::ofstream& out, const std::string& temp, const std::string& path,
                      const std::function<void(std::ostream&)>& write) {
  errno = 0;
  write(out);
  out.flush();
  if (!out) throw InputError(path, "cannot write: " + last_error());
  out.close();
  if (!out) throw InputError(path, "cannot write: " + last_error());
  if (std::rename(temp.c_str(), path.c_str()) != 0) throw InputError(path, "cannot write: " + last_error());
}

}  // namespace

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
