// earshot: head-tracked binaural audio. One executable, one subcommand per job.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>

#include "earshot/errors.hpp"
#include "demo_command.hpp"
#include "render_command.hpp"
#include "scene_commands.hpp"
#include "track_commands.hpp"

int main(int argc, char** argv) {
  CLI::App app{"earshot: head-tracked binaural audio renderer (Wii Remote head tracking + HRTFs)"};
  app.set_version_flag("--version", std::string("earshot ") + EARSHOT_VERSION);
  app.require_subcommand(1);

  auto* track = app.add_subcommand("track", "Head tracking: simulate a camera, solve poses from dots, track live, record");
  track->require_subcommand(1);
  earshot::app::add_track_commands(*track);
  earshot::app::add_demo_command(app);
  earshot::app::add_render_command(app);
  auto* scene = app.add_subcommand("scene", "Scene JSON: list the shipped presets, sample the sources' paths");
  scene->require_subcommand(1);
  earshot::app::add_scene_commands(*scene);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const earshot::InputError& e) {
    std::fprintf(stderr, "earshot: error: %s\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "earshot: error: %s\n", e.what());
    return 1;
  }
  return 0;
}
