// cli/main.cpp — the `mosaic` command-line tool: wires the subcommands and turns every error
// into one line on stderr.
//
// Takes: argv. Gives: the chosen subcommand's output, and an exit status: 0 on success,
// 2 for a malformed command line, 1 for bad input data or a failure while running. Each
// subcommand is one add_<name>_command() in its own <name>_command.cpp.
#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstring>
#include <exception>
#include <iostream>
#include <new>
#include <string>
#include <vector>

#include "cli_common.hpp"
#include "mosaic/errors.hpp"

namespace {

using mosaic::cli::kExitRuntimeError;
using mosaic::cli::kExitUsageError;

// Prints `mosaic: <message>` as exactly one line, whatever the message holds: line breaks and
// tabs become spaces, and the rest of what could drive the terminal is escaped (printable()).
void print_error(const std::string& message) {
  std::string line;
  bool space = false;
  for (char c : message) {
    if (c == '\n' || c == '\r' || c == '\t' || c == ' ') {
      space = !line.empty();
      continue;
    }
    if (space) line += ' ';
    space = false;
    line += c;
  }
  std::cerr << "mosaic: " << (line.empty() ? "unknown error" : mosaic::printable(line))
            << std::endl;
}

// What the program printed (the --stats JSON, the scene list, help; the timing and error lines)
// must have reached stdout and stderr: a full device or a closed pipe is a failure, not a silent
// success. A lost stderr has nowhere to say so, and only the status tells.
int finish_output(int status) {
  errno = 0;
  std::cout.flush();
  if (!std::cout) {
    std::cout.clear();
    print_error(std::string("cannot write to standard output") +
                (errno != 0 ? std::string(": ") + std::strerror(errno) : std::string()));
    status = kExitRuntimeError;
  }
  std::cerr.flush();
  if (!std::cerr && status == 0) status = kExitRuntimeError;
  return status;
}

int run(int argc, char** argv) {
  CLI::App app("mosaic: a SIMD multithreaded tile-based software rasterizer", "mosaic");
  app.require_subcommand(1);
  app.footer(
      "Run `mosaic <command> --help` for a command's options. Exit status: 0 on success, "
      "2 for a malformed command line, 1 for bad input files or a failure while running.");
  const std::vector<mosaic::cli::Command> commands = {
      mosaic::cli::add_render_command(app), mosaic::cli::add_export_command(app),
      mosaic::cli::add_scenes_command(app), mosaic::cli::add_stress_command(app),
      mosaic::cli::add_report_command(app),
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help is a ParseError with exit code 0: print the help as CLI11 does.
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    print_error(e.what());
    return kExitUsageError;
  }
  for (const mosaic::cli::Command& command : commands) {
    if (command.app->parsed()) return command.run();
  }
  print_error("no command given (see mosaic --help)");
  return kExitUsageError;
}

int run_reporting_errors(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const mosaic::cli::UsageError& e) {
    print_error(e.what());
    return kExitUsageError;
  } catch (const mosaic::Error& e) {
    print_error(e.what());
    return kExitRuntimeError;
  } catch (const std::bad_alloc&) {
    print_error("out of memory");
    return kExitRuntimeError;
  } catch (const std::exception& e) {
    print_error(e.what());
    return kExitRuntimeError;
  } catch (...) {
    print_error("unknown error");
    return kExitRuntimeError;
  }
}

}  // namespace

int main(int argc, char** argv) { return finish_output(run_reporting_errors(argc, argv)); }
