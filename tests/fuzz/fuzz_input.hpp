// Shared by the fuzz targets: the readers take paths, so each input is written to a file in a
// per-process scratch folder (on /dev/shm when there is one) and read back by the reader under test.
// A reader may answer bad input only with InputError (exit 2 in the tools); any other exception, a
// crash, a hang or a sanitizer report is a finding, and libFuzzer stops on it.
#pragma once

#include <spdlog/spdlog.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

#include "toolinc/core/error.hpp"

namespace toolinc::fuzz {

inline std::filesystem::path scratch() {
  static const std::filesystem::path dir = [] {
    const std::filesystem::path shm = "/dev/shm";
    auto path = (std::filesystem::is_directory(shm) ? shm : std::filesystem::temp_directory_path()) /
                ("toolinc-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    spdlog::set_level(spdlog::level::off);
    return path;
  }();
  return dir;
}

inline void write_bytes(const std::filesystem::path& path, const std::uint8_t* data, std::size_t size) {
  std::ofstream(path, std::ios::binary | std::ios::trunc)
      .write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
}

// Runs read(); InputError is the expected answer to bad bytes, everything else propagates.
template <class Read>
int expect_only_input_errors(Read&& read) {
  try {
    read();
  } catch (const InputError&) {
  }
  return 0;
}

}  // namespace toolinc::fuzz
