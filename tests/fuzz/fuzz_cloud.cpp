// read_cloud on arbitrary bytes: PLY (ascii, binary little/big endian) and PCD (ascii, binary,
// binary_compressed); built twice (fuzz_ply, fuzz_pcd), each with its own seed corpus.
#include "fuzz_input.hpp"
#include "toolinc/io/cloud_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = toolinc::fuzz::scratch() / "cloud";
  toolinc::fuzz::write_bytes(file, data, size);
  return toolinc::fuzz::expect_only_input_errors([&] {
    const toolinc::PointCloud cloud = toolinc::read_cloud(file.string());
    if (cloud.has_colors() && cloud.colors.size() != cloud.size()) __builtin_trap();
    if (cloud.has_normals() && cloud.normals.size() != cloud.size()) __builtin_trap();
  });
}
