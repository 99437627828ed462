// The conventions every executable shares (docs/formats.md): --help, --version, -o/--output, -c/--config
// (JSON with the same keys as the long options; the command line wins), -v/-q, logging to stderr, and
// exit codes 0 ok, 2 bad usage or input, 3 method failed on valid input, 1 internal error.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace toolinc {

class Command {
 public:
  // config_sections: the sections of a config file this command reads, in order (later ones win);
  // by default the command's own name. Top-level keys of the file are always read.
  Command(std::string name, std::string description, std::vector<std::string> config_sections = {});

  CLI::App& cli() { return cli_; }
  const std::string& name() const { return name_; }
  // The value of -o/--output ("-" is standard output); registered when the command asks for it.
  const std::string& output() const { return output_; }
  CLI::Option* add_output(const std::string& description, bool required = true);

  // The command line as one string, for provenance comments in outputs.
  const std::string& command_line() const { return command_line_; }

  // Parses argv, sets up logging, runs body and maps exceptions to exit codes.
  int run(int argc, char** argv, const std::function<void()>& body);

  // For library callers (the Python module): reads config_file as -c does (when not empty), then parses
  // args (CLI11's reversed order). Throws InputError for the file, CLI::ParseError for the options.
  void parse(std::vector<std::string> args, const std::string& config_file);

 private:
  // The existing files the options other than -o name, so that -o cannot be one of them.
  std::vector<std::string> named_files() const;
  // Reads config_file_ (bounded, naming the file) and makes every floating-point option refuse NaN and
  // infinity. Throws InputError.
  void prepare();

  std::string name_;
  CLI::App cli_;
  std::string output_;
  std::string config_file_;
  std::shared_ptr<nlohmann::ordered_json> config_ =
      std::make_shared<nlohmann::ordered_json>(nlohmann::ordered_json::object());
  std::string command_line_;
  int verbosity_ = 0;
  bool quiet_ = false;
};

}  // namespace toolinc
