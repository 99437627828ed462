#include "toolinc/io/read_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "toolinc/core/error.hpp"
#include "toolinc/io/run_inputs.hpp"

namespace toolinc {
namespace {

std::string kind_of(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode) || S_ISBLK(mode)) return "a device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::size_t checked_size(const std::string& path, const struct stat& st, std::size_t max_bytes) {
  if (!S_ISREG(st.st_mode)) throw InputError(path, "cannot read: " + kind_of(st.st_mode) + ", not a regular file");
  const auto size = static_cast<std::size_t>(st.st_size);
  if (size > max_bytes)
    throw InputError(path, "cannot read: " + std::to_string(size) + " bytes, more than the " +
                               std::to_string(max_bytes) + " allowed");
  return size;
}

}  // namespace

std::size_t check_readable_file(const std::string& path, std::size_t max_bytes) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) throw InputError(path, std::string("cannot open: ") + std::strerror(errno));
  return checked_size(path, st, max_bytes);
}

std::string read_file(const std::string& path, std::size_t max_bytes) {
  check_readable_file(path, max_bytes);  // before open: opening a FIFO or a device can block or act
  // O_NONBLOCK: should the path have become a FIFO since, the open does not wait for a writer.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) throw InputError(path, std::string("cannot open: ") + std::strerror(errno));
  std::string data;
  try {
    struct stat st {};
    if (::fstat(fd, &st) != 0) throw InputError(path, std::string("cannot read: ") + std::strerror(errno));
    data.resize(checked_size(path, st, max_bytes));
    std::size_t done = 0;
    while (done < data.size()) {  // a file that shrinks while read ends early; one that grows is cut
      const ssize_t n = ::read(fd, data.data() + done, data.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw InputError(path, std::string("cannot read: ") + std::strerror(errno));
      if (n == 0) break;
      done += static_cast<std::size_t>(n);
    }
    data.resize(done);
  } catch (...) {
    ::close(fd);
    throw;
  }
  ::close(fd);
  note_input(path);
  return data;
}

}  // namespace toolinc
