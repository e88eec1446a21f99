// spill-sim scene-doc: prints the scene parameter reference (docs/scene_reference.md).

#include <iostream>

#include "sim/commands/command.h"
#include "sph/scene/scene_loader.h"

namespace sim {

Command add_scene_doc_command(CLI::App& app, const CommandContext&) {
  auto* c = app.add_subcommand("scene-doc", "Print the scene parameter reference (Markdown)");
  return {c, [] {
            std::cout << sph::scene_reference_markdown();
            return 0;
          }};
}

}  // namespace sim
