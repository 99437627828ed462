#include "toolinc/app/command.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "toolinc/core/error.hpp"
#include "toolinc/io/json_file.hpp"

namespace toolinc {
namespace {

// A CLI11 config reader for JSON: top-level keys, then each listed section (an object named after a
// command), become option values. Nested objects elsewhere are ignored; they belong to other commands.
class JsonConfig : public CLI::Config {
 public:
  explicit JsonConfig(std::vector<std::string> sections) : sections_(std::move(sections)) {}

  std::string to_config(const CLI::App*, bool, bool, std::string) const override { return {}; }

  std::vector<CLI::ConfigItem> from_config(std::istream& input) const override {
    nlohmann::json json;
    try {
      json = parse_json(std::string(std::istreambuf_iterator<char>(input), {}), "config file");
    } catch (const InputError& e) {
      throw CLI::ConversionError(e.what());
    }
    if (!json.is_object()) throw CLI::ConversionError("config file must hold a JSON object");
    // CLI11 keeps the first value it reads for an option, so the items go most specific first: the
    // last listed section, ..., the first, then the top level.
    std::vector<CLI::ConfigItem> items;
    for (auto section = sections_.rbegin(); section != sections_.rend(); ++section)
      if (json.contains(*section) && json[*section].is_object()) add_items(json[*section], items);
    add_items(json, items);
    return items;
  }

 private:
  static std::string as_input(const nlohmann::json& value) {
    return value.is_string() ? value.get<std::string>() : value.dump();
  }
  static void add_items(const nlohmann::json& object, std::vector<CLI::ConfigItem>& items) {
    for (const auto& [key, value] : object.items()) {
      if (value.is_object() || value.is_null()) continue;
      CLI::ConfigItem item;
      item.name = key;
      if (value.is_array())
        for (const auto& element : value) item.inputs.push_back(as_input(element));
      else
        item.inputs.push_back(as_input(value));
      items.push_back(std::move(item));
    }
  }
  std::vector<std::string> sections_;
};

std::string quote_argument(const std::string& arg) {
  if (!arg.empty() && arg.find_first_of(" \t\n'\"\\$") == std::string::npos) return arg;
  std::string quoted = "'";
  for (char c : arg) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

}  // namespace

Command::Command(std::string name, std::string description, std::vector<std::string> config_sections)
    : name_(std::move(name)), cli_(std::move(description), name_) {
  if (config_sections.empty()) config_sections.push_back(name_);
  cli_.set_version_flag("--version", std::string(name_) + " (toolinc) " + TOOLINC_VERSION);
  cli_.set_config("-c,--config", "", "JSON file with option values (keys = long option names)")
      ->check(CLI::ExistingFile);
  cli_.config_formatter(std::make_shared<JsonConfig>(std::move(config_sections)));
  cli_.allow_config_extras(CLI::config_extras_mode::error);
  cli_.add_flag("-v,--verbose", verbosity_, "More log output (repeat for more)");
  cli_.add_flag("-q,--quiet", quiet_, "Only errors on stderr");
}

CLI::Option* Command::add_output(const std::string& description, bool required) {
  auto* option = cli_.add_option("-o,--output", output_, description);
  if (required) option->required();
  return option;
}

int Command::run(int argc, char** argv, const std::function<void()>& body) {
  command_line_ = name_;  // not argv[0], so outputs do not depend on where the binary lives
  for (int i = 1; i < argc; ++i) command_line_ += " " + quote_argument(argv[i]);
  auto logger = spdlog::stderr_color_mt(name_);
  logger->set_pattern("%n: %^%l%$: %v");
  spdlog::set_default_logger(logger);
  try {
    cli_.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return cli_.exit(e);
  } catch (const CLI::ParseError& e) {
    spdlog::error("{}", e.what());
    std::fprintf(stderr, "Run with --help for more information.\n");
    return 2;
  }
  spdlog::set_level(quiet_ ? spdlog::level::err
                    : verbosity_ >= 2 ? spdlog::level::trace
                    : verbosity_ == 1 ? spdlog::level::debug
                                      : spdlog::level::info);
  try {
    body();
    return 0;
  } catch (const InputError& e) {
    spdlog::error("{}", e.what());
    return 2;
  } catch (const MethodError& e) {
    spdlog::error("{}", e.what());
    return 3;
  } catch (const std::invalid_argument& e) {  // a bad name or value given by the user
    spdlog::error("{}", e.what());
    return 2;
  } catch (const std::exception& e) {
    spdlog::critical("internal error: {}", e.what());
    return 1;
  }
}

}  // namespace toolinc
