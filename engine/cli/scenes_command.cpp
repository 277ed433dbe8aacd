// cli/scenes_command.cpp — `mosaic scenes`: lists the built-in scene names, one per line.
#include <iostream>
#include <string>

#include "cli_common.hpp"
#include "mosaic/scene.hpp"

namespace mosaic::cli {

Command add_scenes_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand("scenes", "List the built-in scenes, one per line");
  return Command{app, [] {
                   for (const std::string& name : builtin_scene_names()) std::cout << name << '\n';
                   return kExitOk;
                 }};
}

}  // namespace mosaic::cli
