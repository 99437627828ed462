// A features-db text file (one vector per line) on arbitrary bytes.
#include "fuzz_input.hpp"
#include "toolinc/appearance/feature_db.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = toolinc::fuzz::scratch() / "0.txt";
  toolinc::fuzz::write_bytes(file, data, size);
  return toolinc::fuzz::expect_only_input_errors([&] {
    const auto rows = toolinc::read_feature_rows(file.string());
    for (const auto& row : rows)
      if (row.size() != rows.front().size() || !row.allFinite()) __builtin_trap();
  });
}
