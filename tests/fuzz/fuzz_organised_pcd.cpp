// read_organised_pcd (a session's points.pcd) on arbitrary bytes: the first two bytes choose the
// expected width and height (1..16), the rest is the file.
#include "fuzz_input.hpp"
#include "toolinc/io/pcd_write.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 2) return 0;
  const int width = 1 + data[0] % 16, height = 1 + data[1] % 16;
  const auto file = toolinc::fuzz::scratch() / "points.pcd";
  toolinc::fuzz::write_bytes(file, data + 2, size - 2);
  return toolinc::fuzz::expect_only_input_errors([&] {
    const toolinc::Points points = toolinc::read_organised_pcd(file.string(), width, height);
    if (points.size() != static_cast<std::size_t>(width) * height) __builtin_trap();
  });
}
