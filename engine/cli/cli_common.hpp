// cli/cli_common.hpp — what every `mosaic` subcommand shares: the subcommand record main.cpp
// wires, the usage-error type, the WxH size option and the SCENE argument.
//
// Takes: command-line strings. Gives: validated sizes and loaded Scenes, or a UsageError
// (exit 2) / mosaic::Error (exit 1) with a one-line message.
#pragma once

#include <CLI/CLI.hpp>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>

#include "mosaic/scene.hpp"

namespace mosaic::cli {

/// Exit status of a run that worked.
inline constexpr int kExitOk = 0;
/// Exit status for bad input data or a failure while running (missing file, parse error, I/O).
inline constexpr int kExitRuntimeError = 1;
/// Exit status for a malformed command line (unknown flag, bad value, wrong combination).
inline constexpr int kExitUsageError = 2;

/// A command line that is well formed for CLI11 but asks for something that makes no sense
/// (e.g. --size for a .tris file). main() prints it as one line and exits with kExitUsageError.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// One subcommand: its CLI11 sub-app, and the action main() runs when it was given. Each
/// subcommand lives in its own <name>_command.cpp and main.cpp only wires them.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

Command add_render_command(CLI::App& parent);
Command add_export_command(CLI::App& parent);
Command add_scenes_command(CLI::App& parent);
Command add_stress_command(CLI::App& parent);
Command add_report_command(CLI::App& parent);

/// A target size given as "WxH".
struct Size {
  int width = 0;
  int height = 0;
};

/// Parses "WxH" (e.g. 1920x1080) with 1 <= W, H <= kMaxTargetSize; nullopt otherwise.
std::optional<Size> parse_size(const std::string& text);
/// A CLI11 validator wrapping parse_size, so a bad --size is a usage error naming the option.
CLI::Validator size_validator();

/// A CLI11 validator for a decimal integer in [lo, hi]. It rejects what CLI11 alone would
/// accept and surprise with (hex, octal "010", trailing text) and normalizes the string it checks.
CLI::Validator integer_in(std::int64_t lo, std::int64_t hi);
/// A CLI11 validator for any unsigned 64-bit decimal integer (e.g. a seed); rejects "-1".
CLI::Validator unsigned_integer();

/// Worker threads a command accepts: kThreadsPerHardwareThread per hardware thread (more is a
/// typo, not a machine), and never more than the Renderer's kMaxThreads.
int max_cli_threads();
/// A CLI11 validator for --threads: an integer from `lo` (0 where 0 means every hardware thread)
/// to max_cli_threads().
CLI::Validator thread_count(int lo);

/// What a SCENE argument names.
enum class SceneKind { kBuiltin, kTris, kObj };

/// Classifies a SCENE argument: a path ending in .tris or .obj, or a built-in scene name.
/// Throws UsageError for anything else, listing the built-in names.
SceneKind classify_scene(const std::string& arg);

/// The SCENE argument and the options that shape it.
struct SceneRequest {
  std::string arg = "default";
  std::optional<Size> size;           ///< --size; built-in and OBJ scenes only
  std::optional<std::uint64_t> seed;  ///< --seed; built-in scenes only
};

/// Builds the requested scene. Throws UsageError when --size or --seed does not apply to the
/// kind of scene, and mosaic::Error when a file is missing or malformed.
Scene load_scene(const SceneRequest& request);

/// The short name of a scene for messages, JSON and the default output file: the built-in
/// name, or the file name without directory and extension.
std::string scene_display_name(const std::string& arg);

/// Lower-case extension of a path including the dot ("" if none), e.g. ".png".
std::string lower_extension(const std::string& path);

}  // namespace mosaic::cli
