// cli/cli_common.cpp — size parsing, SCENE classification and loading for the subcommands.
#include "cli_common.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <filesystem>
#include <iostream>
#include <limits>
#include <system_error>
#include <thread>

#include "mosaic/errors.hpp"
#include "mosaic/renderer.hpp"
#include "mosaic/types.hpp"

namespace mosaic::cli {

namespace {

bool all_digits(std::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), [](char c) {
    return std::isdigit(static_cast<unsigned char>(c)) != 0;
  });
}

template <class T>
std::optional<T> parse_decimal(std::string_view text) {
  T value{};
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

// Parses a whole string of decimal digits into a size in [1, kMaxTargetSize].
std::optional<int> parse_extent(std::string_view digits) {
  const std::optional<int> value = all_digits(digits) ? parse_decimal<int>(digits) : std::nullopt;
  if (!value || *value < 1 || *value > kMaxTargetSize) return std::nullopt;
  return value;
}

// The size a scene gets when --size is not given: the default of Scene itself (1920x1080),
// which is also what builtin_scene() and load_obj() default to.
Size default_size() {
  const Scene defaults;
  return Size{defaults.width, defaults.height};
}

std::string join_names(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) {
    if (!out.empty()) out += ", ";
    out += n;
  }
  return out;
}

}  // namespace

std::optional<Size> parse_size(const std::string& text) {
  const std::size_t x = text.find_first_of("xX");
  if (x == std::string::npos) return std::nullopt;
  const std::string_view view(text);
  const std::optional<int> w = parse_extent(view.substr(0, x));
  const std::optional<int> h = parse_extent(view.substr(x + 1));
  if (!w || !h) return std::nullopt;
  return Size{*w, *h};
}

CLI::Validator size_validator() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        if (parse_size(value)) return {};
        return "expected WxH with 1 <= W, H <= " + std::to_string(kMaxTargetSize) + ", got '" +
               value + "'";
      },
      "");
}

CLI::Validator integer_in(std::int64_t lo, std::int64_t hi) {
  const std::string range =
      hi >= std::numeric_limits<int>::max()
          ? "an integer >= " + std::to_string(lo)
          : "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
  return CLI::Validator(
      [lo, hi, range](std::string& value) -> std::string {
        const bool negative = !value.empty() && value.front() == '-';
        const std::string_view digits = std::string_view(value).substr(negative ? 1 : 0);
        const std::optional<std::int64_t> parsed =
            all_digits(digits) ? parse_decimal<std::int64_t>(value) : std::nullopt;
        if (!parsed || *parsed < lo || *parsed > hi)
          return "expected " + range + ", got '" + value + "'";
        value = std::to_string(*parsed);
        return {};
      },
      "");
}

int max_cli_threads() {
  // Four per hardware thread leaves room for oversubscription tests; a count past that is a typo.
  constexpr int kThreadsPerHardwareThread = 4;
  const int hardware = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  return std::min(kMaxThreads, kThreadsPerHardwareThread * hardware);
}

CLI::Validator thread_count(int lo) {
  CLI::Validator range = integer_in(lo, max_cli_threads());
  range.description("threads from " + std::to_string(lo) + " to " +
                    std::to_string(max_cli_threads()) + " (4 per hardware thread)");
  return range;
}

CLI::Validator unsigned_integer() {
  return CLI::Validator(
      [](std::string& value) -> std::string {
        const std::optional<std::uint64_t> parsed =
            all_digits(value) ? parse_decimal<std::uint64_t>(value) : std::nullopt;
        if (!parsed) return "expected an integer from 0 to 2^64-1, got '" + value + "'";
        value = std::to_string(*parsed);
        return {};
      },
      "");
}

std::string lower_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

SceneKind classify_scene(const std::string& arg) {
  const std::string ext = lower_extension(arg);
  if (ext == ".tris") return SceneKind::kTris;
  if (ext == ".obj") return SceneKind::kObj;
  const std::vector<std::string> names = builtin_scene_names();
  if (std::find(names.begin(), names.end(), arg) != names.end()) return SceneKind::kBuiltin;
  // A file that exists is bad input (status 1), not a malformed command line: its name does not
  // say which format it is in.
  std::error_code ec;
  if (std::filesystem::exists(arg, ec))
    throw mosaic::Error(mosaic::Errc::kInvalidArgument,
                        arg +
                            ": a scene file must be named *.tris or *.obj (the "
                            "extension, in any case, chooses the format)");
  throw UsageError("unknown scene '" + arg + "': give a built-in scene (" + join_names(names) +
                   ") or a .tris or .obj file");
}

std::string scene_display_name(const std::string& arg) {
  if (classify_scene(arg) == SceneKind::kBuiltin) return arg;
  return std::filesystem::path(arg).stem().string();
}

Scene load_scene(const SceneRequest& request) {
  switch (classify_scene(request.arg)) {
    case SceneKind::kBuiltin: {
      const Size size = request.size.value_or(default_size());
      return builtin_scene(request.arg, size.width, size.height, request.seed.value_or(1));
    }
    case SceneKind::kTris:
      if (request.size)
        throw UsageError("--size does not apply to .tris files: their 'size' line sets it");
      if (request.seed) throw UsageError("--seed applies to built-in scenes only");
      return load_tris(request.arg);
    case SceneKind::kObj: {
      if (request.seed) throw UsageError("--seed applies to built-in scenes only");
      const Size size = request.size.value_or(default_size());
      Scene scene = load_obj(request.arg, size.width, size.height);
      for (const std::string& w : scene.warnings) std::cerr << "mosaic: warning: " << w << '\n';
      return scene;
    }
  }
  throw UsageError("unknown scene '" + request.arg + "'");
}

}  // namespace mosaic::cli
