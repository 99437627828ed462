// report SESSION_OUTPUTS -o REPORT.html: one self-contained HTML page of a session's pipeline outputs
// (renders, merge table, tool frame, tooltip, errors against a ground truth).
#include "toolinc/report/report.hpp"

#include <spdlog/spdlog.h>

#include "toolinc/app/command.hpp"
#include "toolinc/io/atomic_file.hpp"

int main(int argc, char** argv) {
  toolinc::Command command("report", "One self-contained HTML page of a session's pipeline outputs");
  std::string dir;
  command.cli()
      .add_option("outputs", dir,
                  "A session's pipeline outputs: merge_report.json, frame.json, tooltip.json, model.png, "
                  "sheet.png and, for a session with a ground truth, evaluation.json")
      ->required();
  command.add_output("Output HTML");
  return command.run(argc, argv, [&] {
    const std::string html = toolinc::report_html(toolinc::read_session_outputs(dir));
    toolinc::write_file_atomic(
        command.output(), [&](std::ostream& out) { out << html; }, /*binary=*/true);
    spdlog::info("wrote {} ({} kB)", command.output(), html.size() / 1024);
  });
}
