// Hand-built cloud files: byte encoders, a binary_compressed PCD around a given stream, and the check that
// reading a file fails as bad input naming it.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>

#include "toolinc/core/error.hpp"
#include "toolinc/io/cloud_io.hpp"

namespace toolinc::testing {

// Explicit byte order, independent of the host.
template <class T>
std::string bytes_of(T value, bool big_endian = false) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  const std::uint16_t one = 1;
  const bool host_big = *reinterpret_cast<const unsigned char*>(&one) == 0;
  std::string out(reinterpret_cast<const char*>(raw), sizeof(T));
  if (big_endian != host_big) std::reverse(out.begin(), out.end());
  return out;
}

inline std::string u8(int value) { return std::string(1, static_cast<char>(value)); }

// A binary_compressed PCD of `points` points whose uncompressed data is `raw` and stream `compressed`.
inline std::string compressed_pcd(const std::string& fields_header, std::size_t points, const std::string& raw,
                                  const std::string& compressed) {
  return "VERSION 0.7\n" + fields_header + "WIDTH " + std::to_string(points) + "\nHEIGHT 1\nPOINTS " +
         std::to_string(points) + "\nDATA binary_compressed\n" +
         bytes_of(static_cast<std::uint32_t>(compressed.size())) + bytes_of(static_cast<std::uint32_t>(raw.size())) +
         compressed;
}

// read_cloud(file) must throw an InputError whose message names the file and contains `word`.
inline void expect_read_error(const std::string& file, const std::string& word) {
  try {
    read_cloud(file);
    ADD_FAILURE() << "no error reading " << file;
  } catch (const InputError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find(file), std::string::npos) << message;
    EXPECT_NE(message.find(word), std::string::npos) << message;
  }
}

}  // namespace toolinc::testing
