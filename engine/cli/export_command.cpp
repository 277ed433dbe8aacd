// cli/export_command.cpp — `mosaic export`: writes a scene as a screen-space .tris file.
//
// Takes: a SCENE (built-in name or .obj; a .tris is re-written as is) and --out FILE.tris.
// Gives: the .tris file (mosaic::save_tris) and one human line on stderr.
#include <iostream>
#include <memory>
#include <string>

#include "cli_common.hpp"
#include "mosaic/mosaic.hpp"

namespace mosaic::cli {

namespace {

struct ExportOptions {
  SceneRequest scene;
  std::string out;
  std::string size;
  std::uint64_t seed = 1;
  CLI::Option* size_opt = nullptr;
  CLI::Option* seed_opt = nullptr;
};

int run_export(const ExportOptions& o) {
  if (lower_extension(o.out) != ".tris")
    throw UsageError("--out: '" + o.out + "' must end in .tris");
  SceneRequest request = o.scene;
  if (o.size_opt->count() > 0) request.size = parse_size(o.size);
  if (o.seed_opt->count() > 0) request.seed = o.seed;
  const Scene scene = load_scene(request);
  save_tris(scene, o.out);
  std::cerr << printable(scene_display_name(o.scene.arg)) << " " << scene.width << "x"
            << scene.height << ": " << scene.triangle_count() << " triangles -> "
            << printable(o.out) << '\n';
  return kExitOk;
}

}  // namespace

Command add_export_command(CLI::App& parent) {
  auto o = std::make_shared<ExportOptions>();
  CLI::App* app =
      parent.add_subcommand("export", "Write a built-in or OBJ scene as a screen-space .tris file");
  app->add_option("SCENE", o->scene.arg, "A built-in scene (see `mosaic scenes`) or a .obj file")
      ->required();
  app->add_option("--out", o->out,
                  "The .tris file to write (renamed into place: a symlink at FILE is replaced, "
                  "never written through)")
      ->type_name("FILE")
      ->required();
  o->size_opt = app->add_option("--size", o->size, "Target size WxH (default 1920x1080)")
                    ->type_name("WxH")
                    ->check(size_validator());
  o->seed_opt = app->add_option("--seed", o->seed, "Random seed of built-in scenes (default 1)")
                    ->type_name("UINT")
                    ->transform(unsigned_integer());
  return Command{app, [o] { return run_export(*o); }};
}

}  // namespace mosaic::cli
