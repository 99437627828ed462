// A tool's config file (-c FILE: JSON whose keys are long option names) on arbitrary bytes, through
// the same Command every executable uses. Bad files must end in a usage error (exit 2), never a crash.
#include "fuzz_input.hpp"
#include "toolinc/app/command.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = toolinc::fuzz::scratch() / "config.json";
  toolinc::fuzz::write_bytes(file, data, size);
  spdlog::drop("estimate-frame");  // Command registers its logger by name, once per run
  toolinc::Command command("estimate-frame", "fuzzed configuration");
  double tolerance = 0.005;
  int samples = 100;
  std::vector<double> box{0, 0, 0};
  std::string name;
  bool flag = false;
  auto& cli = command.cli();
  cli.add_option("--tolerance", tolerance, "a length");
  cli.add_option("--samples", samples, "a count");
  cli.add_option("--box", box, "three numbers")->expected(3);
  cli.add_option("--name", name, "a string");
  cli.add_flag("--flag", flag, "a flag");
  std::string config = file.string();
  std::string program = "estimate-frame", option = "-c", quiet = "-q";
  char* argv[] = {program.data(), option.data(), config.data(), quiet.data(), nullptr};
  const int code = command.run(4, argv, [] {});
  if (code != 0 && code != 2) __builtin_trap();  // 1 would be an internal error
  return 0;
}
