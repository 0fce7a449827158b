// `pilelab check`: every table of scene files read by its stage's reader (apps/scene_check.h).
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "apps/scene_check.h"

namespace pilelab::app {

void add_check_command(CLI::App& app) {
  auto scenes = std::make_shared<std::vector<std::string>>();
  CLI::App* cmd = app.add_subcommand(
      "check", "Check scene files: every table is read by its stage's reader (unknown keys, types, ranges),\n"
               "files the scene reads exist, and the pour's cost is estimated (steps, grain-steps, time on one core);\n"
               "nothing is run. Exit code 2 at the first scene with an error.");
  cmd->add_option("scenes", *scenes, "Scene files (TOML); see docs/SCENES.md")->required()->check(CLI::ExistingFile);
  cmd->final_callback([scenes] {
    for (const std::string& path : *scenes) {
      const SceneCheck check = check_scene(path, /*estimate_cost=*/true);
      std::string tables;
      for (const std::string& t : check.tables) tables += (tables.empty() ? "" : ", ") + t;
      std::printf("%s: ok (%s)\n", path.c_str(), tables.empty() ? "no tables: every stage takes its defaults" : tables.c_str());
      if (check.pour_cost) std::printf("  %s\n", cost_text(check).c_str());
    }
  });
}

}  // namespace pilelab::app
