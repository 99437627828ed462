// A tool's config file (-c FILE: JSON whose keys are long option names) on arbitrary bytes, through
// the same Command every executable uses, with estimate-frame's range-checked parameter table and options
// of each kind beside it. Bad files must end in a usage error (exit 2), never a crash, and a file accepted
// must leave every parameter inside its range.
#include "fuzz_input.hpp"
#include "toolinc/app/command.hpp"
#include "toolinc/app/options.hpp"
#include "toolinc/app/range.hpp"
#include "toolinc/frame/parameters.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto file = toolinc::fuzz::scratch() / "config.json";
  toolinc::fuzz::write_bytes(file, data, size);
  spdlog::drop("estimate-frame");  // Command registers its logger by name, once per run
  toolinc::Command command("estimate-frame", "fuzzed configuration");
  toolinc::ToolFrameConfig frame;
  double tolerance = 0.005;
  int samples = 100;
  std::vector<double> box{0, 0, 0};
  std::string name;
  bool flag = false;
  auto& cli = command.cli();
  toolinc::add_tool_frame_options(cli, frame);
  cli.add_option("--tolerance", tolerance, "a length")->check(toolinc::in_range({1e-4, false, 2, "m"}));
  cli.add_option("--samples", samples, "a count")->check(toolinc::in_range({0, true, 1e7, ""}));
  cli.add_option("--box", box, "three numbers")->expected(3);
  cli.add_option("--name", name, "a string");
  cli.add_flag("--flag", flag, "a flag");
  std::string config = file.string();
  std::string program = "estimate-frame", option = "-c", quiet = "-q";
  char* argv[] = {program.data(), option.data(), config.data(), quiet.data(), nullptr};
  const int code = command.run(4, argv, [] {});
  if (code != 0 && code != 2) __builtin_trap();  // 1 would be an internal error
  if (code == 0)
    for (const auto& p : toolinc::tool_frame_parameters()) {
      const double value = toolinc::value_of(p, frame);
      if (!(p.min_exclusive ? value > p.min : value >= p.min) || !(value <= p.max)) __builtin_trap();
    }
  return 0;
}
