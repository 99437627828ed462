#include "toolinc/app/command.hpp"

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <iterator>
#include <memory>
#include <nlohmann/json.hpp>
#include <opencv2/core/utils/logger.hpp>

#include "toolinc/core/error.hpp"
#include "toolinc/io/json_file.hpp"
#include "toolinc/io/read_file.hpp"
#include "toolinc/io/run_inputs.hpp"

namespace toolinc {
namespace {

// A CLI11 config reader for JSON: top-level keys, then each listed section (an object named after a
// command), become option values. Nested objects elsewhere are ignored; they belong to other commands.
// The file was read and parsed by Command::run beforehand (bounded, naming the file); CLI11 opens it
// again only to hand over a stream, which is then not read.
class JsonConfig : public CLI::Config {
 public:
  JsonConfig(std::vector<std::string> sections, std::shared_ptr<const nlohmann::ordered_json> json)
      : sections_(std::move(sections)), json_(std::move(json)) {}

  std::string to_config(const CLI::App*, bool, bool, std::string) const override { return {}; }

  std::vector<CLI::ConfigItem> from_config(std::istream&) const override {
    const nlohmann::ordered_json& json = *json_;
    // CLI11 keeps the first value it reads for an option, so the items go most specific first: the
    // last listed section, ..., the first, then the top level.
    std::vector<CLI::ConfigItem> items;
    for (auto section = sections_.rbegin(); section != sections_.rend(); ++section)
      if (json.contains(*section) && json[*section].is_object()) add_items(json[*section], items);
    add_items(json, items);
    return items;
  }

 private:
  static std::string as_input(const nlohmann::ordered_json& value) {
    return value.is_string() ? value.get<std::string>() : value.dump();
  }
  static void add_items(const nlohmann::ordered_json& object, std::vector<CLI::ConfigItem>& items) {
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
  std::shared_ptr<const nlohmann::ordered_json> json_;
};

// The -c/--config value in argv, in any of CLI11's spellings, or "".
std::string config_argument(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "-c" || arg == "--config") && i + 1 < argc) return argv[i + 1];
    if (arg.rfind("--config=", 0) == 0) return arg.substr(9);
    if (arg.size() > 2 && arg.rfind("-c", 0) == 0 && arg[2] != '-') return arg.substr(2);
    if (arg == "--") break;
  }
  return {};
}

// Every floating-point option: strtod reads "nan", "inf" and 1e400 (as inf), which no range check
// catches (every comparison with NaN is false).
const CLI::Validator& finite_number() {
  static const CLI::Validator validator(
      [](std::string& value) -> std::string {
        char* end = nullptr;
        const double x = std::strtod(value.c_str(), &end);
        if (end == value.c_str()) return {};  // not a number at all: the conversion reports it
        return std::isfinite(x) ? std::string() : "must be a finite number, not " + value;
      },
      "FINITE");
  return validator;
}

bool mentions_option(const std::string& message, const std::string& key) {
  const std::string option = "--" + key;
  for (std::size_t at = message.find(option); at != std::string::npos; at = message.find(option, at + 1)) {
    const std::size_t after = at + option.size();
    if (after == message.size() || !(std::isalnum(static_cast<unsigned char>(message[after])) || message[after] == '-'))
      return true;
  }
  return false;
}

bool on_command_line(const std::string& key, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--" + key || arg.rfind("--" + key + "=", 0) == 0) return true;
  }
  return false;
}

// A value the config file gave, or a key it should not have, is the config file's error: say so.
std::string usage_error(const CLI::ParseError& e, const std::string& config_file, const nlohmann::ordered_json& config,
                        int argc, char** argv) {
  const std::string message = e.what();
  if (config_file.empty()) return message;
  if (dynamic_cast<const CLI::ConfigError*>(&e)) return config_file + ": " + message;
  for (const auto& item : config.items()) {
    const auto check = [&](const std::string& key) {
      return mentions_option(message, key) && !on_command_line(key, argc, argv);
    };
    if (check(item.key())) return config_file + ": " + message;
    if (item.value().is_object())
      for (const auto& nested : item.value().items())
        if (check(nested.key())) return config_file + ": " + message;
  }
  return message;
}

// A method failure names its input when the message does not already name one of the run's files.
std::string method_error(const std::string& message, const std::string& config_file) {
  const std::vector<std::string> inputs = run_inputs();
  for (const auto& input : inputs)
    if (message.find(input) != std::string::npos) return message;
  for (const auto& input : inputs)
    if (input != config_file) return input + ": " + message;
  return message;
}

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
  cli_.set_config("-c,--config", "", "JSON file with option values (keys = long option names)");
  cli_.config_formatter(std::make_shared<JsonConfig>(std::move(config_sections), config_));
  cli_.allow_config_extras(CLI::config_extras_mode::error);
  cli_.add_flag("-v,--verbose", verbosity_, "More log output (repeat for more)");
  cli_.add_flag("-q,--quiet", quiet_, "Only errors on stderr");
}

CLI::Option* Command::add_output(const std::string& description, bool required) {
  auto* option = cli_.add_option("-o,--output", output_, description);
  if (required) option->required();
  return option;
}

std::vector<std::string> Command::named_files() const {
  std::vector<std::string> files;
  std::error_code ec;
  for (const CLI::Option* option : cli_.get_options()) {
    if (option->check_name("--output")) continue;
    for (const std::string& value : option->results())
      if (!value.empty() && std::filesystem::is_regular_file(value, ec)) files.push_back(value);
  }
  return files;
}

void Command::prepare() {
  if (!config_file_.empty()) *config_ = parse_json(read_file(config_file_, kMaxJsonBytes), config_file_);
  if (!config_->is_object()) throw InputError(config_file_, "a config file must hold a JSON object");
  for (CLI::Option* option : cli_.get_options()) {
    const bool floating = option->get_type_name().rfind("FLOAT", 0) == 0;
    // Each check of a number first names a NaN or an infinity as such, and CLI11's positive and
    // non-negative checks say so: alone they call a value out of a range whose bound is the largest double,
    // 309 digits long. (CLI11 keeps no count of an option's checks: the index runs out.)
    for (int i = 0;; ++i) {
      CLI::Validator* check = nullptr;
      try {
        check = option->get_validator(i);
      } catch (const CLI::OptionNotFound&) {
        break;
      }
      const CLI::Validator inner = *check;
      const std::string kind = check->get_description();
      check->operation([inner, kind, floating](std::string& value) {
        const std::string not_finite = floating ? finite_number()(value) : std::string();
        if (!not_finite.empty()) return not_finite;
        const std::string error = inner(value);
        if (error.empty() || (kind != "POSITIVE" && kind != "NONNEGATIVE")) return error;
        return (kind == "POSITIVE" ? "must be positive, not " : "must be zero or positive, not ") + value;
      });
    }
    if (floating) option->check(finite_number());
  }
}

void Command::parse(std::vector<std::string> args, const std::string& config_file) {
  config_file_ = config_file;
  prepare();
  if (!config_file.empty()) args.insert(args.begin(), {config_file, "--config"});
  cli_.parse(args);
}

int Command::run(int argc, char** argv, const std::function<void()>& body) {
  command_line_ = name_;  // not argv[0], so outputs do not depend on where the binary lives
  for (int i = 1; i < argc; ++i) command_line_ += " " + quote_argument(argv[i]);
  auto logger = spdlog::stderr_color_mt(name_);
  logger->set_pattern("%n: %^%l%$: %v");
  spdlog::set_default_logger(logger);
  track_inputs();
  // Beyond `ulimit -f` a write then fails with EFBIG, reported and its temporary file removed, instead of
  // the signal killing the process mid-write.
  std::signal(SIGXFSZ, SIG_IGN);
  config_file_ = config_argument(argc, argv);
  try {
    prepare();
  } catch (const InputError& e) {
    spdlog::error("{}", e.what());
    return 2;
  }
  try {
    cli_.parse(argc, argv);
  } catch (const CLI::Success& e) {
    return cli_.exit(e);
  } catch (const CLI::ParseError& e) {
    spdlog::error("{} (see --help)", usage_error(e, config_file_, *config_, argc, argv));
    return 2;
  }
  // A spelling config_argument does not know would leave the file unread: say so rather than ignore it.
  const CLI::Option* config = cli_.get_config_ptr();
  if (config->count() > 0 && config->as<std::string>() != config_file_) {
    spdlog::error("{}: give a config file as -c FILE, -cFILE, --config FILE or --config=FILE",
                  config->as<std::string>());
    return 2;
  }
  spdlog::set_level(quiet_            ? spdlog::level::err
                    : verbosity_ >= 2 ? spdlog::level::trace
                    : verbosity_ == 1 ? spdlog::level::debug
                                      : spdlog::level::info);
  // OpenCV's logger prints lines of its own (the ONNX importer's errors, which it also throws and we report
  // in one line naming the file): heard only with -v.
  cv::utils::logging::setLogLevel(verbosity_ >= 1 && !quiet_ ? cv::utils::logging::LOG_LEVEL_WARNING
                                                             : cv::utils::logging::LOG_LEVEL_SILENT);
  try {
    check_not_among(output_, named_files());
    body();
    return 0;
  } catch (const InputError& e) {
    spdlog::error("{}", e.what());
    return 2;
  } catch (const MethodError& e) {
    spdlog::error("{}", method_error(e.what(), config_file_));
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
